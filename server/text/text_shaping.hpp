// Shaping: the text's lines cut into runs of one script and direction
// (numbers stay left to right inside right-to-left text), each shaped by
// HarfBuzz with the requested features, and the runs ordered on the line by
// its base direction. Positions in font units.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/status.hpp"
#include "text/font_face.hpp"
#include "text/text_settings.hpp"

namespace surfdeform {

struct ShapedGlyph {
  uint32_t glyph = 0;    // glyph index in the font
  uint32_t cluster = 0;  // byte offset of its cluster in the text
  double x_advance = 0.0, y_advance = 0.0, x_offset = 0.0, y_offset = 0.0;  // font units
};

struct ShapedRun {
  std::string script;  // ISO 15924, as HarfBuzz resolved it
  bool rtl = false;
  bool joining = false;             // a script whose letters join (letter spacing stays out)
  std::vector<ShapedGlyph> glyphs;  // in visual order, left to right
};

struct ShapedLine {
  std::vector<ShapedRun> runs;  // in visual order
  bool rtl = false;             // the line's base direction
};

// The text's code points, decoded; kMalformed for bytes that are not UTF-8.
Result<std::u32string> DecodeUtf8(const std::string& text);
std::string EncodeUtf8(char32_t c);

// The code points of `text` the font has no glyph for (controls and line
// breaks aside), each once, in order of appearance.
std::vector<char32_t> MissingCodePoints(const FontFace& font, const std::u32string& text);

// kInvalidArgument for an unknown script, language or feature (naming
// "text.script", ...).
Result<std::vector<ShapedLine>> ShapeText(const FontFace& font, const TextSettings& settings);

}  // namespace surfdeform
