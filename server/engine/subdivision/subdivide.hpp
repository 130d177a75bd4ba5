// Refining a model where the surface bends, before it is deformed (the
// paper's section 3.2: vertex, edge and face points).
//
// A face larger than the cells of the flat grid is deformed as a flat
// triangle between its three deformed corners, so it cuts through the
// surface. The model is laid on the flat sheet (placement.hpp) and:
//  - vertex points are its vertices;
//  - edge points are where its edges, projected on the sheet, cross the flat
//    grid lines (the images of u = i / (nu - 1) and v = j / (nv - 1));
//  - face points are the flat grid nodes inside its projected faces.
// A grid line crossing a face runs from one edge point to another through the
// face points between them: a chord. Reduction (the paper's marking rules, to
// a fixed point over the whole mesh): an edge or face point is kept where the
// surface's curvature there exceeds epsilon (for an edge point: the normal
// curvature along the edge; for a face point: the largest principal
// curvature); a chord with a kept point is kept whole (its opposite edge point
// too, and its face points, so the face follows the grid line); a kept face
// point whose curvature exceeds epsilon keeps the other chord through it
// (Figure 6 b); a kept edge point is kept for both faces of its edge, which
// may keep a chord of the neighbour. Points are considered only in faces
// larger than a grid cell (a projected edge longer than the sides of the
// cells it crosses), as the paper subdivides only such faces: a fine model
// (the bunny) is left as it is. One extension: the paper tests face points
// only on chords already kept, which misses a bump inside a large face whose
// sides lie where the surface is flat; here every face point is tested.
//
// Tolerance: the largest distance between the refined, deformed mesh and the
// exact deformation of the model, in output units (the surface's). A straight
// segment of length l on a surface of normal curvature k strays k l^2 / 8 from
// it, so a tolerance t asks for the grid points of a face of size l where the
// curvature exceeds 8 t / l^2: that is the epsilon a tolerance implies, and it
// is applied per face together with the given epsilon. Then every edge and
// face is measured against the exact deformation (the deformed position of
// each output point is compared with the exact image of the model point it
// stands for) and refined further where needed, inside cells too: edges by
// bisection (an edge's points depend only on that edge), faces by splitting
// interior edges (Delaunay). The tolerance is then met at every measured
// point, up to the output-size limit, past which the request fails.
//
// Conforming: edge points depend only on the edge's end positions and the
// marks, which are shared by both faces of an edge (edges are matched by
// position, so a texture seam does not open a crack); each face is
// re-triangulated from its kept points with its sides fixed. A closed,
// manifold input stays closed and manifold; faces keep their orientation.
// New vertices get every attribute interpolated (normals and tangents
// renormalised); they follow the input's vertices, whose order is kept.
//
// Modes: kOff, kAdaptive (the rules above), kUniform (every edge and face
// point of every face kept, no extra refinement: the reference that adaptive
// is compared with). Deterministic: the same output whatever the thread count.
//
// The pipeline (server/engine/subdivision/, one file per stage, each taking
// and returning explicit structs):
//   vertex_location   each input vertex's cell, on-sheet flag, position
//   cell_estimates    curvature, twist and kinks per cell: the estimate
//   screen            a fine model that needs nothing stops here
//   edge_graph        vertices welded by position, edges, faces
//   grid_marking      edge and face points, the marking rules
//   edge_refinement   each edge's final points (bisection to the tolerance)
//   face_refinement   each face re-triangulated (face_retriangulation) and
//                     refined (triangle_deviation) to the tolerance
//   assembly          the refined mesh and the statistics
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "base/cancel_flag.hpp"
#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "engine/sheet/sheet_footprint.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/subdivision/subdivision_settings.hpp"

namespace surfdeform {

const char* SubdivisionModeName(SubdivisionMode mode);  // "off", "adaptive", "uniform"

// A subdivision as the engine runs it: the request's settings, the
// service's output limits and budget, and threads.
struct SubdivisionOptions : SubdivisionSettings {
  size_t max_vertices = 4'000'000;   // output size limit (vertices)
  size_t max_triangles = 8'000'000;  // and triangles
  // The model's edges' crossings of the grid lines (or of a mesh surface's
  // edges), each kept to be measured and maybe marked: over it, kLimitExceeded
  // before they are all stored.
  size_t max_crossings = 32'000'000;
  // Wall-clock budget of the call, ms; 0 = none. Past it the subdivision
  // stops with kDeadlineExceeded (checked between its phases and per edge and
  // face while refining, so it stops within one face's work of the budget).
  double time_budget_ms = 0.0;
  const CancelFlag* cancel = nullptr;  // raised: the subdivision stops as at its budget's end
  int threads = 0;                     // 0 = one per core; results do not depend on it
};

// The options with `mode`, everything else at its default.
inline SubdivisionOptions SubdivisionIn(SubdivisionMode mode) {
  SubdivisionOptions o;
  o.mode = mode;
  return o;
}

struct SubdivisionStats {
  SubdivisionMode mode = SubdivisionMode::kOff;
  size_t vertices_before = 0;
  size_t triangles_before = 0;
  size_t vertices_after = 0;
  size_t triangles_after = 0;
  size_t edge_points_considered = 0;  // grid-line crossings of edges in large faces
  size_t edge_points_kept = 0;
  size_t face_points_considered = 0;  // grid nodes inside large faces
  size_t face_points_kept = 0;
  size_t refinement_points = 0;  // added inside cells for the tolerance
  double epsilon = 0.0;          // as used
  double tolerance = 0.0;        // as used (0: none)
  double max_deviation = 0.0;    // the largest measured, output units
  size_t measured_points = 0;    // where the deviation was measured
  // Edges and faces inside one cell, far below the tolerance by an estimate
  // from the curvature there, are not measured: the largest such estimate.
  double max_estimated_deviation = 0.0;
  double time_ms = 0.0;
};

// Whether the caller wants the deformed positions of the input vertices (a
// deformation that carries no normals or tangents reuses them; one that does
// needs the map's Jacobian at every vertex anyway).
enum class InputPositions { kNotWanted, kWanted };

struct SubdivisionResult {
  // Nothing to add: the input stands as it is (then mesh and placed are empty).
  bool unchanged = false;
  Mesh mesh;                 // model coordinates; the input's vertices first, in order
  std::vector<Vec3> placed;  // placed coordinates (a, b, h) of every vertex of `mesh`
  // Per input vertex: its footprint is on the sheet (empty in mode kOff).
  std::vector<char> on_sheet;
  // With InputPositions::kWanted (and a mode other than kOff): the deformed
  // position of each input vertex, computed as the deformation computes it
  // (OffsetAlongNormal at its exact parameters: NaN where the normal
  // vanishes); meaningful only where on_sheet.
  std::optional<std::vector<Vec3>> input_positions;
  SubdivisionStats stats;
};

Status ValidateSubdivision(const SubdivisionOptions& options);

// A face's extent on the sheet, which its curvature estimate needs: its
// longest side in placed coordinates, squared, and the spread and the largest
// magnitude of its corners' heights. It depends on the placed model only, not
// on the sheet: a model laid on many sheets (the frames of an animation)
// measures it once (FaceExtents) for all of them.
struct FaceExtent {
  double longest2, dh, h;
};
std::vector<FaceExtent> FaceExtents(const Mesh& mesh, const std::vector<Vec3>& placed);

// Refines `mesh` (model coordinates; `placed` holds each vertex's placed
// coordinates, an affine image of the model) for deformation through `map`.
// `outside` is the placement's mode: points of new vertices that fall outside
// the sheet follow it (kError: extrapolated, since the vertices themselves
// were checked). Errors: kLimitExceeded with the limit and the size reached
// when the output would exceed max_vertices or max_triangles.
// `extents`, when given, is FaceExtents(mesh, placed) (one per triangle), so
// that it is not measured again. `footprint` says where the input vertices
// lie on the sheet, or records it (sheet_footprint.hpp).
Result<SubdivisionResult> Subdivide(const Mesh& mesh, const std::vector<Vec3>& placed,
                                    const SheetMap& map, OutsideMode outside,
                                    const SubdivisionOptions& options,
                                    InputPositions want = InputPositions::kNotWanted,
                                    std::span<const FaceExtent> extents = {},
                                    const FootprintUse& footprint = {});

}  // namespace surfdeform
