// Stage 7a of the subdivision: a face re-triangulated from its kept points.
//
// The face's own frame (corner 0 at the origin, corner 1 on +x, corner 2
// above: counter-clockwise, so triangles keep the face's orientation; a face
// of nearly zero area gets its barycentric frame instead), its sides split at
// their edges' final points in the face's direction, its kept face points
// inserted, and its kept chords through them constrained (a constrained
// Delaunay triangulation, FaceTriangulation). Each point knows where it came
// from, for assembly, and its deformed position, for the deviation.
#pragma once

#include <optional>

#include "engine/subdivision/cell_estimates.hpp"
#include "engine/subdivision/edge_refinement.hpp"
#include "engine/subdivision/face_triangulation.hpp"
#include "engine/subdivision/grid_marking.hpp"

namespace surfdeform::subdivision {

// What the face stages read, from the stages before them.
struct FaceStageInputs {
  const Context& ctx;
  const EdgeGraph& graph;
  const GridMarking& marking;
  const IdVector<EdgeId, RefinedEdge>& edges;
  const LocatedVertices& located;
  const CellEstimates& estimates;
};

// A point of a face's re-triangulation beyond its corners.
struct LocalPoint {
  enum class Kind : uint8_t { kOnSide, kInside };
  Kind kind = Kind::kInside;
  int side = 0;               // kOnSide: on side k (edge k), the index-th of the edge's
  int index = 0;              // final points in the edge's own order
  double l1 = 0.0, l2 = 0.0;  // barycentric coordinates of corners 1 and 2
};

struct FaceWork {
  FaceWork(const Eigen::Matrix2d& frame, const Vec3& f0, const Vec3& f1, const Vec3& f2);

  Eigen::Matrix2d frame;    // barycentric (l1, l2) -> the face's frame
  Eigen::Matrix2d to_bary;  // its inverse
  FaceTriangulation tri;
  std::vector<Vec3> fval;         // per triangulation point: its deformed position
  std::vector<LocalPoint> local;  // per point past the three corners

  void Add(const LocalPoint& p, const Vec3& deformed) {
    local.push_back(p);
    fval.push_back(deformed);
  }
  Vec2 Bary(const Vec2& in_frame) const { return to_bary * in_frame; }
};

// The face's frame (see above), as the matrix from barycentric coordinates.
Eigen::Matrix2d FaceFrame(const Context& ctx, const std::array<VertexId, 3>& corners);

// The face re-triangulated from its final side points, kept face points and
// kept chords. Empty when an invariant of the triangulation broke (a bug),
// or when `budget` (if given) ran out of time: it is looked at every 32
// points inserted and chord pieces constrained, since a long thin face with
// thousands of points on its sides takes seconds (each side point inserted
// flips the fan across to the other sides; each constraint walks round a
// point's fan).
std::optional<FaceWork> TriangulateFace(const FaceStageInputs& in, FaceId f, int* hint,
                                        Budget* budget = nullptr);

}  // namespace surfdeform::subdivision
