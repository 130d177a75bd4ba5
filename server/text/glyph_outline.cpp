#include "text/glyph_outline.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H

#include <algorithm>
#include <cmath>

#include "text/font_face_impl.hpp"

namespace surfdeform {
namespace {

// Past this many chords a piece is refused by the point limits anyway.
constexpr double kMaxPieces = 1 << 16;

int PiecesFor(double bound, double tolerance) {
  // A chord over parameter length h of a curve whose second derivative is
  // at most B is within B h^2 / 8 of it.
  if (!(bound > 0.0)) return 1;
  const double n = std::ceil(std::sqrt(bound / (8.0 * tolerance)));
  return static_cast<int>(std::clamp(n, 1.0, kMaxPieces));
}

Vec2 V(const FT_Vector* v) { return {static_cast<double>(v->x), static_cast<double>(v->y)}; }

struct Decomposer {
  double tolerance;
  size_t max_points;
  bool count_only;
  GlyphOutline* out;
  size_t count = 0;
  Vec2 pen = Vec2::Zero();
  bool too_many = false;

  void Emit(const Vec2& p) {
    ++count;
    if (count > max_points) {
      too_many = true;
      return;
    }
    if (count_only) return;
    auto& c = out->contours.back();
    if (c.empty() || (c.back() - p).squaredNorm() > 0.0) c.push_back(p);
  }
};

int MoveTo(const FT_Vector* to, void* user) {
  auto* d = static_cast<Decomposer*>(user);
  if (!d->count_only) d->out->contours.emplace_back();
  d->pen = V(to);
  d->Emit(d->pen);
  return d->too_many ? 1 : 0;
}

int LineTo(const FT_Vector* to, void* user) {
  auto* d = static_cast<Decomposer*>(user);
  d->pen = V(to);
  d->Emit(d->pen);
  return d->too_many ? 1 : 0;
}

int ConicTo(const FT_Vector* control, const FT_Vector* to, void* user) {
  auto* d = static_cast<Decomposer*>(user);
  const Vec2 p0 = d->pen, p1 = V(control), p2 = V(to);
  const int n = QuadraticPieces(p0, p1, p2, d->tolerance);
  for (int k = 1; k <= n && !d->too_many; ++k) {
    const double t = static_cast<double>(k) / n, s = 1.0 - t;
    d->Emit(s * s * p0 + 2.0 * s * t * p1 + t * t * p2);
  }
  d->pen = p2;
  return d->too_many ? 1 : 0;
}

int CubicTo(const FT_Vector* c1, const FT_Vector* c2, const FT_Vector* to, void* user) {
  auto* d = static_cast<Decomposer*>(user);
  const Vec2 p0 = d->pen, p1 = V(c1), p2 = V(c2), p3 = V(to);
  const int n = CubicPieces(p0, p1, p2, p3, d->tolerance);
  for (int k = 1; k <= n && !d->too_many; ++k) {
    const double t = static_cast<double>(k) / n, s = 1.0 - t;
    d->Emit(s * s * s * p0 + 3.0 * s * s * t * p1 + 3.0 * s * t * t * p2 + t * t * t * p3);
  }
  d->pen = p3;
  return d->too_many ? 1 : 0;
}

Result<FT_Outline*> LoadOutline(const FontFace& font, uint32_t glyph) {
  FT_Face face = font.impl().face;
  if (glyph >= static_cast<uint32_t>(face->num_glyphs)) {
    return Status(ErrorCode::kMalformed,
                  "glyph " + std::to_string(glyph) + " is not in the font (it has " +
                      std::to_string(face->num_glyphs) + ")",
                  "font");
  }
  const FT_Error e =
      FT_Load_Glyph(face, glyph, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP);
  if (e != 0 || face->glyph->format != FT_GLYPH_FORMAT_OUTLINE) {
    const char* why = FT_Error_String(e);
    return Status(ErrorCode::kMalformed,
                  "glyph " + std::to_string(glyph) +
                      " cannot be read: " + (why != nullptr ? why : "no outline"),
                  "font");
  }
  FT_Outline* o = &face->glyph->outline;
  const auto points = static_cast<size_t>(o->n_points);
  if (points > font.limits().max_glyph_points) {
    return Status::LimitExceeded(
        "glyph " + std::to_string(glyph) + " has more outline points than the limit", "font",
        static_cast<double>(font.limits().max_glyph_points), static_cast<double>(points));
  }
  return o;
}

Status Decompose(FT_Outline* o, Decomposer* d) {
  FT_Outline_Funcs funcs{};
  funcs.move_to = MoveTo;
  funcs.line_to = LineTo;
  funcs.conic_to = ConicTo;
  funcs.cubic_to = CubicTo;
  const FT_Error e = FT_Outline_Decompose(o, &funcs, d);
  if (d->too_many) {
    return Status::LimitExceeded(
        "the outline at this tolerance needs more points than the limit; raise "
        "text.tolerance_mm or shorten the text",
        "text.tolerance_mm", static_cast<double>(d->max_points), static_cast<double>(d->count));
  }
  if (e != 0) return Status(ErrorCode::kMalformed, "a glyph's outline is broken", "font");
  return Status::Ok();
}

}  // namespace

int QuadraticPieces(const Vec2& p0, const Vec2& p1, const Vec2& p2, double tolerance) {
  return PiecesFor(2.0 * (p0 - 2.0 * p1 + p2).norm(), tolerance);
}

int CubicPieces(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3, double tolerance) {
  const double m = std::max((p0 - 2.0 * p1 + p2).norm(), (p1 - 2.0 * p2 + p3).norm());
  return PiecesFor(6.0 * m, tolerance);
}

Result<GlyphOutline> LoadGlyphOutline(const FontFace& font, uint32_t glyph, double tolerance,
                                      size_t max_points) {
  SURFDEFORM_ASSIGN_OR_RETURN(FT_Outline * o, LoadOutline(font, glyph));
  GlyphOutline out;
  out.even_odd = (o->flags & FT_OUTLINE_EVEN_ODD_FILL) != 0;
  out.font_points = static_cast<size_t>(o->n_points);
  Decomposer d{tolerance, max_points, false, &out};
  SURFDEFORM_RETURN_IF_ERROR(Decompose(o, &d));
  // Closed implicitly: a last point equal to the first goes; so do
  // contours that enclose nothing.
  auto& cs = out.contours;
  for (auto& c : cs) {
    if (c.size() > 1 && (c.front() - c.back()).squaredNorm() == 0.0) c.pop_back();
  }
  cs.erase(std::remove_if(cs.begin(), cs.end(), [](const auto& c) { return c.size() < 3; }),
           cs.end());
  return out;
}

Result<size_t> CountGlyphPoints(const FontFace& font, uint32_t glyph, double tolerance) {
  SURFDEFORM_ASSIGN_OR_RETURN(FT_Outline * o, LoadOutline(font, glyph));
  Decomposer d{tolerance, static_cast<size_t>(-1), true, nullptr};
  SURFDEFORM_RETURN_IF_ERROR(Decompose(o, &d));
  return d.count;
}

}  // namespace surfdeform
