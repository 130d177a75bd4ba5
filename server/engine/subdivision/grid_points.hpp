// The paper's edge and face points (section 3.2): where a segment on the flat
// sheet crosses the flat grid lines, and which grid nodes lie inside a
// triangle on the sheet; and the surface curvatures that decide which are kept.
//
// Grid lines: u-line i joins the nodes (i, 0) .. (i, nv - 1) of the flat sheet
// (the image of u = i / (nu - 1)), v-line j the nodes (0, j) .. (nu - 1, j).
// Between two nodes a line is straight on the sheet (a side of a cell), so a
// crossing is a segment-segment intersection. A position along a line is
// given by the index of the node it passes plus the fraction to the next.
#pragma once

#include <vector>

#include "engine/common/geometry_types.hpp"
#include "engine/sheet/flat_locator.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

// A point where a segment crosses grid lines: one line, or two where it
// passes through a node.
struct GridCrossing {
  double t = 0.0;        // along the segment, (0, 1)
  int u_line = -1;       // u-line index i, or -1
  double u_along = 0.0;  // position along it (j + fraction)
  int v_line = -1;       // v-line index j, or -1
  double v_along = 0.0;  // position along it (i + fraction)
};

// The crossings of segment a-b with the grid lines, by increasing t.
// Crossings closer than 1e-7 of the segment's length to an end are dropped
// (the end stands for them); crossings of two lines that coincide are merged.
// Segments (nearly) along a line do not cross it. `scratch` avoids
// allocations across calls. Also returns, in *min_cell_side, the shortest
// side of the cells near the segment (infinity when there are none).
void GridCrossings(const FlatLocator& locator, const Vec2& a, const Vec2& b,
                   std::vector<GridCrossing>* out, std::vector<int>* scratch,
                   double* min_cell_side);

// A grid node inside a triangle, with the triangle's barycentric coordinates
// of corners 1 and 2 (corner 0's is 1 - l1 - l2).
struct GridNodeInside {
  int i = 0;
  int j = 0;
  double l1 = 0.0;
  double l2 = 0.0;
};

// The grid nodes strictly inside the triangle a, b, c (either orientation),
// at least 1e-7 of the triangle's size from its sides, ordered by (j, i). None
// for a triangle of (nearly) zero area.
void GridNodesInside(const FlatLocator& locator, const Vec2& a, const Vec2& b, const Vec2& c,
                     std::vector<GridNodeInside>* out, std::vector<int>* scratch);

// The normal curvature of the surface at s in parameter direction (du, dv),
// 1 / surface units, signed (positive: bending towards the normal).
double NormalCurvature(const SurfacePoint& s, const Vec2& duv);

// The largest absolute principal curvature at s.
double MaxAbsCurvature(const SurfacePoint& s);

}  // namespace surfdeform
