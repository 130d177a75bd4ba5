// Stage 1 of the subdivision: where each input vertex lands.
//
// For every input vertex: its sheet cell (-1 off the sheet), whether it is on
// the sheet, and its deformed position, computed as the deformation computes
// it (OffsetAlongNormal at its exact parameters) so that the deformation can
// reuse it. When the caller does not want the positions up front (it will
// recompute them with the map's Jacobian anyway), only the parameters are
// kept, and CompleteDeformed fills the positions if the refinement needs them.
#pragma once

#include "engine/subdivision/context.hpp"

namespace surfdeform::subdivision {

struct LocatedVertices {
  IdVector<VertexId, int> cell;       // sheet cell, -1 off the sheet
  IdVector<VertexId, char> on_sheet;  // 1: on the sheet
  IdVector<VertexId, Vec3> deformed;  // positions (empty until computed)
  IdVector<VertexId, Vec2> uv;        // parameters, when positions were deferred
  size_t outside = 0;                 // how many are off the sheet
  double outside_worst = 0.0;         // the farthest, sheet units
};

// Locates every input vertex; with `positions`, deforms it too. Errors:
// kOutsideSheet (as the deformation reports it) when outside = kError and a
// vertex is off the sheet, before any work is spent refining.
Result<LocatedVertices> LocateVertices(const Context& ctx, bool positions);

// Fills `located->deformed` when LocateVertices deferred it.
void CompleteDeformed(const Context& ctx, LocatedVertices* located);

}  // namespace surfdeform::subdivision
