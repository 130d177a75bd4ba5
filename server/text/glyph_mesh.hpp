// A glyph's outline as a solid: the filled region (by the outline's fill
// rule, so overlapping contours fill once and holes stay holes) split by
// CGAL's constrained Delaunay triangulation, and extruded to a depth: a
// closed, consistently oriented (outward) triangle mesh, or with depth 0
// the region alone, facing +z.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"
#include "text/glyph_outline.hpp"

namespace surfdeform {

struct GlyphSolid {
  std::vector<Vec3> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  double area = 0.0;  // of the filled region, in the outline's units squared
};

// `outline` in any units; `scale` multiplies them (font units to mm);
// `depth` in the scaled units. kDegenerate when the CDT fails on the
// outline (it does not for any outline FreeType gives).
Result<GlyphSolid> MeshGlyph(const std::vector<std::vector<Vec2>>& contours, bool even_odd,
                             double scale, double depth);

}  // namespace surfdeform
