// What a request says about a text model ("text" of POST /v1/deform and
// /v1/animate): the string, the font, its size and depth in millimetres, how
// it is shaped and set, and the line it follows on the sheet. Plain
// vocabulary, which the API's request types (proto/) share with the
// typesetter (text_model.hpp says what each does).
#pragma once

#include <string>
#include <vector>

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform {

enum class TextAlign { kLeft, kCenter, kRight };
inline constexpr EnumEntry<TextAlign> kTextAligns[] = {
    {TextAlign::kLeft, "left", "each line starts at the path's start (the centre's left)"},
    {TextAlign::kCenter, "center", "each line is centred (the default)"},
    {TextAlign::kRight, "right", "each line ends at the path's end"},
};

enum class TextDirection { kAuto, kLtr, kRtl };
inline constexpr EnumEntry<TextDirection> kTextDirections[] = {
    {TextDirection::kAuto, "auto",
     "each line's direction from its first strong letter; runs of another script in the "
     "line keep their own direction (the default)"},
    {TextDirection::kLtr, "ltr", "left to right"},
    {TextDirection::kRtl, "rtl", "right to left"},
};

// The baseline on the sheet: a straight line through the placement's centre
// along the sheet's u direction (turned by placement.rotation_deg), a circle
// of radius arc_mm through it (positive: the text on the outside of the
// circle, reading clockwise; negative: inside, reading anticlockwise), or a
// polyline given in sheet coordinates (then it is where the text goes, and
// the placement's centre, rotation and scale are the points').
enum class TextPathKind { kStraight, kArc, kSheetPoints };
struct TextPath {
  TextPathKind kind = TextPathKind::kStraight;
  double arc_mm = 0.0;
  std::vector<Vec2> sheet_points;
};

struct TextSettings {
  std::string string;               // UTF-8; "\n" starts a new line
  std::string font = "DejaVuSans";  // a built-in font's name, or an uploaded font's id
  double size_mm = 4.0;             // the font's em
  double depth_mm = 0.6;            // extrusion; 0: flat letters, one sided
  double letter_spacing_mm = 0.0;   // added after each cluster (not inside joined scripts)
  double line_spacing = 1.2;        // baseline to baseline, in ems
  TextAlign align = TextAlign::kCenter;
  TextDirection direction = TextDirection::kAuto;
  std::string script = "auto";    // ISO 15924 ("Latn", "Arab", ...) or "auto"
  std::string language = "auto";  // BCP 47 ("en", "ar", "hi", ...) or "auto"
  // OpenType features as HarfBuzz spells them ("kern", "liga", "-liga",
  // "smcp", "ss01=1"). Kerning and ligatures are on only when listed.
  std::vector<std::string> features = {"kern", "liga"};
  double tolerance_mm = 0.01;  // the outlines' largest distance from the font's curves
  TextPath path;
};

// The smallest em a tolerance can represent: a stroke of 1/16 em (the
// thinnest of ordinary text faces) keeps both sides apart at twice the
// tolerance: size >= 32 x tolerance.
inline constexpr double kMinSizeInTolerances = 32.0;

// Ranges of the numbers and the shape of the path; kInvalidArgument naming
// the field ("text.size_mm"). `field` is the settings' JSON path ("text").
Status ValidateTextSettings(const TextSettings& settings, const std::string& field = "text");

}  // namespace surfdeform
