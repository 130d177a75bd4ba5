// Text as a model: the string shaped (text_shaping.hpp), each glyph's
// outline flattened to the tolerance (glyph_outline.hpp) and made a solid
// (glyph_mesh.hpp), set along the baseline's path, in millimetres. One group
// per glyph, named by the text of its cluster, so that rigid "groups" keep
// each glyph whole and the stats can name it; every glyph is its own
// closed, outward-oriented solid (or, with depth 0, one-sided letters
// facing +z).
#pragma once

#include <string>
#include <vector>

#include "base/cancel_flag.hpp"
#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "text/font_face.hpp"
#include "text/text_settings.hpp"

namespace surfdeform {

struct TextGlyph {
  uint32_t glyph = 0;   // glyph index in the font
  std::string cluster;  // the text it stands for ("f", "ffi", "\u0633")
  int line = 0;
  double s_mm = 0.0;                       // its centre's arc length along its line's baseline
  double advance_mm = 0.0;                 // along the baseline
  Vec2 origin = Vec2::Zero();              // its origin on the layout plane (mm)
  double rotation = 0.0;                   // radians, counter-clockwise
  size_t group = static_cast<size_t>(-1);  // its group in the mesh (none: a space)
};

struct TextModel {
  Mesh mesh;  // in mm: x along the baseline, y up the letters, z out of the sheet
  std::vector<TextGlyph> glyphs;
  int lines = 0;
  double width_mm = 0.0;          // the longest line's advance
  double path_length_mm = 0.0;    // of a sheet_points or arc path (0: straight)
  size_t outline_points = 0;      // after flattening
  double area_mm2 = 0.0;          // of the letters' faces
  std::vector<std::string> runs;  // each run's script and direction ("Latn ltr")
  bool in_sheet_units = false;    // sheet_points: the layout plane is the sheet
};

// The model for `settings` in `font`. Errors: kInvalidArgument naming
// "text.string" for code points the font lacks (MissingCodePoints first
// gives them to say which fonts have them), "text.path" for text longer
// than its path, "text.size_mm" / "text.depth_mm" below what the tolerance
// can represent (saying the smallest that works); kLimitExceeded for the
// font's and the text's limits; kUnavailable-free: a raised `cancel` stops
// it with kDeadlineExceeded.
Result<TextModel> MakeTextModel(const FontFace& font, const TextSettings& settings,
                                const CancelFlag* cancel = nullptr);

// The smallest size_mm / depth_mm a tolerance can represent.
double MinTextSize(double tolerance_mm);
double MinTextDepth(double tolerance_mm);

}  // namespace surfdeform
