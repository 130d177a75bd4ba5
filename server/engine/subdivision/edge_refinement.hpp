// Stage 6 of the subdivision: each edge's final points.
//
// An edge keeps its marked grid crossings. With a tolerance, each piece
// between them is measured against the exact deformation (at its quarter
// points, and at the crossings inside it that were not kept, where the map
// has kinks) and bisected at its worst sample until it is within kEdgeShare
// of the tolerance; an edge inside one 2 x 2 block whose estimate is small
// enough is not measured. The points depend on the edge alone, so both faces
// of an edge get the same ones: the result is conforming.
#pragma once

#include "engine/subdivision/cell_estimates.hpp"
#include "engine/subdivision/grid_marking.hpp"
#include "engine/subdivision/vertex_location.hpp"

namespace surfdeform::subdivision {

struct RefinedEdge {
  std::vector<double> kept_t;  // final points, by t in (0, 1)
  std::vector<Vec3> kept_f;    // their deformed positions
  Tally tally;
};

// Stops early (leaving edges unrefined) once `budget` is out of time; counts
// each added point against it.
IdVector<EdgeId, RefinedEdge> RefineEdges(const Context& ctx, const EdgeGraph& graph,
                                          const GridMarking& marking,
                                          const LocatedVertices& located,
                                          const CellEstimates& estimates, Budget* budget);

}  // namespace surfdeform::subdivision
