#include "text/text_settings.hpp"

#include <cctype>
#include <cmath>

#include "base/format.hpp"

namespace surfdeform {
namespace {

Status Bad(const std::string& message, const std::string& field) {
  return Status(ErrorCode::kInvalidArgument, message, field);
}

Status InRange(double x, double lo, double hi, bool lo_open, const std::string& field) {
  const bool ok = std::isfinite(x) && (lo_open ? x > lo : x >= lo) && x <= hi;
  if (ok) return Status::Ok();
  return Bad("must be in " + std::string(lo_open ? "(" : "[") + Num(lo) + ", " + Num(hi) +
                 "], got " + Num(x),
             field);
}

}  // namespace

Status ValidateTextSettings(const TextSettings& s, const std::string& f) {
  if (s.string.empty()) return Bad("must not be empty", f + ".string");
  if (s.font.empty() || s.font.size() > 128) {
    return Bad("must name a font: GET /v1/fonts lists them (or an uploaded font's id)",
               f + ".font");
  }
  SURFDEFORM_RETURN_IF_ERROR(InRange(s.size_mm, 0.0, 10000.0, true, f + ".size_mm"));
  SURFDEFORM_RETURN_IF_ERROR(InRange(s.depth_mm, 0.0, 10000.0, false, f + ".depth_mm"));
  SURFDEFORM_RETURN_IF_ERROR(
      InRange(s.letter_spacing_mm, -10000.0, 10000.0, false, f + ".letter_spacing_mm"));
  SURFDEFORM_RETURN_IF_ERROR(InRange(s.line_spacing, 0.0, 100.0, true, f + ".line_spacing"));
  SURFDEFORM_RETURN_IF_ERROR(InRange(s.tolerance_mm, 1e-6, 100.0, false, f + ".tolerance_mm"));
  if (s.script != "auto") {
    bool ok = s.script.size() == 4;
    for (char c : s.script) ok = ok && std::isalpha(static_cast<unsigned char>(c));
    if (!ok) {
      return Bad("must be \"auto\" or an ISO 15924 code (\"Latn\", \"Arab\", \"Deva\"), got \"" +
                     s.script + "\"",
                 f + ".script");
    }
  }
  if (s.language != "auto") {
    bool ok = !s.language.empty() && s.language.size() <= 35;
    for (char c : s.language) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '-');
    if (!ok) {
      return Bad(
          "must be \"auto\" or a BCP 47 tag (\"en\", \"ar\", \"hi\"), got \"" + s.language + "\"",
          f + ".language");
    }
  }
  if (s.features.size() > 64) {
    return Bad("lists more than 64 features (" + std::to_string(s.features.size()) + ")",
               f + ".features");
  }
  switch (s.path.kind) {
    case TextPathKind::kStraight:
      break;
    case TextPathKind::kArc:
      if (!std::isfinite(s.path.arc_mm) || s.path.arc_mm == 0.0 || std::abs(s.path.arc_mm) > 1e6) {
        return Bad("must be a radius in mm, non-zero and within +-1e6, got " + Num(s.path.arc_mm),
                   f + ".path.arc_mm");
      }
      break;
    case TextPathKind::kSheetPoints: {
      const auto& pts = s.path.sheet_points;
      const std::string field = f + ".path.sheet_points";
      if (pts.size() < 2 || pts.size() > 65536) {
        return Bad("must have from 2 to 65536 points, got " + std::to_string(pts.size()), field);
      }
      for (size_t k = 0; k < pts.size(); ++k) {
        if (!pts[k].allFinite() || pts[k].cwiseAbs().maxCoeff() > 1e15) {
          return Bad("must be finite and within +-1e15", field + "[" + std::to_string(k) + "]");
        }
        if (k > 0 && (pts[k] - pts[k - 1]).norm() == 0.0) {
          return Bad("repeats the point before it", field + "[" + std::to_string(k) + "]");
        }
      }
      break;
    }
  }
  return Status::Ok();
}

}  // namespace surfdeform
