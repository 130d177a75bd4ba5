// Stage 3 of the subdivision: the screen, which decides before any edge is
// built whether the model needs nothing at all.
//
// A model finer than the grid, on a surface that bends gently at its scale
// (the paper's dolphin, the bunny): every face inside a 2 x 2 block of cells
// and none larger than a cell, all within the tolerance by the cells'
// estimate or, where that is not small enough, measured as the full
// refinement would measure them (each edge at its quarter points and grid
// crossings, the face at its centroid). Then the mesh stays as it is.
#pragma once

#include "engine/subdivision/cell_estimates.hpp"
#include "engine/subdivision/vertex_location.hpp"

namespace surfdeform::subdivision {

struct ScreenResult {
  bool pass = false;           // nothing to add
  double max_estimate = 0.0;   // the largest estimate of the faces not measured
  double max_deviation = 0.0;  // the largest measured
  size_t measured_points = 0;
};

// Only with a tolerance to screen against (ctx.refine); otherwise no pass.
// The corners' positions come from `located.deformed` when it is filled, else
// from the map.
ScreenResult Screen(const Context& ctx, const LocatedVertices& located,
                    const CellEstimates& estimates);

}  // namespace surfdeform::subdivision
