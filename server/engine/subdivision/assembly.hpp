// Stage 8 of the subdivision: the refined mesh.
//
// The input's vertices first, in order; then, face by face, the points each
// face added: a side's points once per pair of input vertices (both faces of
// an edge share them; a texture seam has two pairs at the same positions, so
// the same points with their own attributes), a face's inside points once.
// Every attribute of a new vertex is interpolated from the input vertices it
// lies between (normals and tangents renormalised, the tangent's sign by the
// weighted majority). Groups cover the refined triangles of their faces. The
// statistics of every stage are summed here.
#pragma once

#include "engine/subdivision/face_refinement.hpp"

namespace surfdeform::subdivision {

// Errors: kLimitExceeded when the mesh passes max_vertices or max_triangles.
// `stats` holds what the earlier stages counted; the result's adds the rest.
Result<SubdivisionResult> Assemble(const Context& ctx, const EdgeGraph& graph,
                                   const GridMarking& marking,
                                   const IdVector<EdgeId, RefinedEdge>& edges,
                                   const IdVector<FaceId, FaceOutput>& faces,
                                   const SubdivisionStats& stats);

}  // namespace surfdeform::subdivision
