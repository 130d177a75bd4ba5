// A font file opened for one piece of work: FreeType reads it (TrueType,
// OpenType CFF, WOFF, WOFF2) inside a memory budget of its own, and
// HarfBuzz shapes with it through FreeType's tables. Nothing here reads a
// file: the bytes are the caller's (a built-in font read at start, or an
// upload), and they must outlive the face.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.hpp"

namespace surfdeform {

// What a font may cost, each published in GET /v1/info.
struct FontLimits {
  size_t max_font_bytes = 16u << 20;   // the file
  size_t max_font_memory = 64u << 20;  // FreeType's heap while it reads the file (WOFF2 inflates)
  size_t max_glyphs = 65535;           // glyphs in the font
  size_t max_glyph_points = 20000;     // outline points of one glyph
  size_t max_text_cost = 4u << 20;     // glyphs x points of one text, before meshing
  size_t max_text_code_points = 4096;  // code points of one text
};

// The scripts whose coverage is reported: ISO 15924 and a letter each
// font must map to be said to cover it.
struct ScriptProbe {
  const char* script;  // "Latn"
  const char* name;    // "Latin"
  std::vector<char32_t> letters;
};
const std::vector<ScriptProbe>& ScriptProbes();

struct FontInfo {
  std::string family;
  std::string style;
  std::string format;  // "truetype", "cff", "woff2", ...
  size_t glyphs = 0;
  int units_per_em = 0;
  std::vector<std::string> scripts;  // ISO 15924 codes of ScriptProbes() it covers
};

class FontFace {
 public:
  // kMalformed (a 400: "font") for bytes FreeType does not read as a font
  // or that break a limit on the way (kLimitExceeded for the bytes, the
  // glyph count and FreeType's memory, with the limit and the value).
  static Result<std::unique_ptr<FontFace>> Open(std::string_view bytes, const FontLimits& limits);
  ~FontFace();
  FontFace(const FontFace&) = delete;
  FontFace& operator=(const FontFace&) = delete;

  const FontInfo& info() const { return info_; }
  const FontLimits& limits() const { return limits_; }
  bool HasCodePoint(char32_t c) const;
  // The glyph's outline in font units, through FT_Outline_Decompose's
  // callbacks (glyph_outline.hpp); the face's own FT types stay in the .cpp.
  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  FontFace(const FontLimits& limits);
  FontLimits limits_;
  FontInfo info_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace surfdeform
