// Stage 3b of the subdivision: how many points it will add at least, known
// before any is added, so that a request past the output limit is refused
// in microseconds rather than after the limit is reached by minutes of work
// and gigabytes (a 50-byte model laid across 1e30 units of the sheet, or a
// tolerance of 1e-9).
//
// Two lower bounds, summed over the faces (placed coordinates, before any
// clamping: a clamped or extrapolated face is refined over all of its
// extent):
//  - grid points: a face larger than a cell gets the grid nodes inside its
//    footprint, area / cell area (the cell of the sheet's bounding box,
//    larger than the average cell);
//  - tolerance points: a segment of length l on a surface of curvature k
//    strays k l^2 / 8 from it, so meeting a tolerance t takes pieces of
//    sqrt(8 t / k) or less: k / (8 t) of them per unit of area, where a
//    surface bent in one direction only (a cylinder) could take long thin
//    triangles, the fewest; k is the smallest curvature of the cells the
//    face's corners lie in (0 where one is off the sheet).
// Measured on the paper's plate fitted on a unit cylinder (tolerances 1e-4,
// 1e-5, 1e-6: 8,698, 92,903 and 995,499 points added), the bound is 0.53,
// 0.50 and 0.46 of the points actually added.
#pragma once

#include "engine/subdivision/cell_estimates.hpp"
#include "engine/subdivision/context.hpp"
#include "engine/subdivision/vertex_location.hpp"

namespace surfdeform::subdivision {

struct WorkEstimate {
  double grid_points = 0.0;
  double tolerance_points = 0.0;
  double tolerance = 0.0;  // as resolved
  double total() const { return grid_points + tolerance_points; }
};

WorkEstimate EstimateWork(const Context& ctx, const LocatedVertices& located,
                          const CellEstimates& estimates);

}  // namespace surfdeform::subdivision
