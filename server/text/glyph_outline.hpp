// A glyph's outline as closed polygons: FreeType's contours in font units,
// each quadratic or cubic piece cut into as many equal-parameter chords as
// its second derivative needs to stay within the tolerance (Wang's bound),
// and no more.
#pragma once

#include <cstdint>
#include <vector>

#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"
#include "text/font_face.hpp"

namespace surfdeform {

struct GlyphOutline {
  std::vector<std::vector<Vec2>> contours;  // closed: the last point joins the first
  bool even_odd = false;                    // the font's fill rule (else non-zero)
  size_t font_points = 0;                   // the font's own points (control points too)
  size_t points() const {
    size_t n = 0;
    for (const auto& c : contours) n += c.size();
    return n;
  }
};

// The chords a quadratic (p0, p1, p2) or cubic piece needs for `tolerance`.
int QuadraticPieces(const Vec2& p0, const Vec2& p1, const Vec2& p2, double tolerance);
int CubicPieces(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3, double tolerance);

// The outline of glyph `glyph` (a glyph index, not a code point) in font
// units, flattened to `tolerance` font units. kLimitExceeded when the glyph
// has more points than the font limits allow, or flattening would make more
// than `max_points`; kMalformed for a glyph FreeType cannot load.
Result<GlyphOutline> LoadGlyphOutline(const FontFace& font, uint32_t glyph, double tolerance,
                                      size_t max_points);

// The number of points LoadGlyphOutline would make, from the font's curves
// alone (for a text's cost before any flattening).
Result<size_t> CountGlyphPoints(const FontFace& font, uint32_t glyph, double tolerance);

}  // namespace surfdeform
