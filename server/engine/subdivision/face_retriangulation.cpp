#include "engine/subdivision/face_retriangulation.hpp"

#include <algorithm>

namespace surfdeform::subdivision {
namespace {

constexpr size_t kPointsPerTimeCheck = 32;

// Whether the budget (if any) ran out, looked at every kPointsPerTimeCheck
// points inserted or chords constrained (`inserted`, counted here).
bool OutOfTime(Budget* budget, size_t* inserted) {
  return budget != nullptr && ++*inserted % kPointsPerTimeCheck == 0 && budget->OutOfTime();
}

// Splits the face's sides at their edges' final points, in the face's
// direction; the ids of each side's points by the edge's own order. False
// when the triangulation did not number them in order (cannot happen: sides
// are only split here).
bool SplitSides(const FaceStageInputs& in, const GraphFace& face, FaceWork* w,
                std::array<std::vector<int>, 3>* side_ids, Budget* budget, size_t* inserted) {
  const Vec2 corner_bary[3] = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
  for (int k = 0; k < 3; ++k) {
    const RefinedEdge& e = in.edges[face.edge[k]];
    const size_t m = e.kept_t.size();
    (*side_ids)[k].assign(m, -1);
    int prev = k;
    const int next = (k + 1) % 3;
    for (size_t q = 0; q < m; ++q) {
      if (OutOfTime(budget, inserted)) return false;
      const size_t idx = face.reversed[k] ? m - 1 - q : q;
      const double t = face.reversed[k] ? 1.0 - e.kept_t[idx] : e.kept_t[idx];
      const Vec2 l = corner_bary[k] + t * (corner_bary[next] - corner_bary[k]);
      const int id = w->tri.SplitBoundary(prev, next, w->frame * l);
      if (id != static_cast<int>(w->fval.size())) return false;
      w->Add({LocalPoint::Kind::kOnSide, k, static_cast<int>(idx), l.x(), l.y()}, e.kept_f[idx]);
      (*side_ids)[k][idx] = id;
      prev = id;
    }
  }
  return true;
}

// Inserts the kept face points; their triangulation ids (-1: not inserted).
// False when the budget ran out.
bool InsertFacePoints(const FaceStageInputs& in, const GraphFace& face, const FaceMarks& marks,
                      FaceWork* w, int* hint, Budget* budget, size_t* inserted,
                      std::vector<int>* ids) {
  std::vector<int>& point_ids = *ids;
  point_ids.assign(marks.points.size(), -1);
  for (size_t q = 0; q < marks.points.size(); ++q) {
    if (!marks.points[q].kept) continue;
    if (OutOfTime(budget, inserted)) return false;
    const GridNodeInside& node = marks.points[q].node;
    const int id = w->tri.Insert(w->frame * Vec2(node.l1, node.l2));
    if (id < 0) continue;
    if (id == static_cast<int>(w->fval.size())) {
      w->Add({LocalPoint::Kind::kInside, 0, 0, node.l1, node.l2},
             in.ctx.Deformed(in.ctx.InTriangle(face.corner, node.l1, node.l2), hint));
    }
    point_ids[q] = id;
  }
  return true;
}

// Constrains the kept chords between the points they pass through. False
// when the budget ran out (each constraint walks round a point's fan, which
// on a long thin face holds thousands of triangles).
bool ConstrainChords(const FaceStageInputs& in, FaceId fi, const std::vector<int>& point_ids,
                     const std::array<std::vector<int>, 3>& side_ids, FaceWork* w, Budget* budget,
                     size_t* inserted) {
  const GraphFace& face = in.graph.faces[fi];
  for (const Chord& chord : Chords(in.ctx, in.graph, in.marking, fi)) {
    if (!ChordKept(in.ctx, in.graph, in.marking, fi, chord)) continue;
    int prev = -1;
    for (const ChordEntry& e : chord.entries) {
      int id = -1;
      if (!e.IsEdgePoint()) {
        id = point_ids[e.ref];
      } else {
        const EdgeId edge = face.edge[e.side];
        const double t = in.marking.edges[edge].points[e.ref].crossing.t;
        const std::vector<double>& kept = in.edges[edge].kept_t;
        const auto it = std::lower_bound(kept.begin(), kept.end(), t);
        if (it != kept.end() && *it == t) id = side_ids[e.side][it - kept.begin()];
      }
      if (id < 0) continue;
      if (prev >= 0) {
        if (OutOfTime(budget, inserted)) return false;
        w->tri.Constrain(prev, id);
      }
      prev = id;
    }
  }
  if (budget != nullptr && budget->OutOfTime()) return false;
  w->tri.RestoreDelaunay();
  return true;
}

}  // namespace

FaceWork::FaceWork(const Eigen::Matrix2d& frame_in, const Vec3& f0, const Vec3& f1, const Vec3& f2)
    : frame(frame_in),
      to_bary(frame_in.inverse()),
      tri(Vec2::Zero(), frame_in.col(0), frame_in.col(1)),
      fval{f0, f1, f2} {}

Eigen::Matrix2d FaceFrame(const Context& ctx, const std::array<VertexId, 3>& corners) {
  const Vec3 e1 = ctx.Placed(corners[1]) - ctx.Placed(corners[0]);
  const Vec3 e2 = ctx.Placed(corners[2]) - ctx.Placed(corners[0]);
  const Vec3 nrm = e1.cross(e2);
  Vec2 q1(1, 0), q2(0, 1);
  if (nrm.norm() > 1e-12 * e1.norm() * e2.norm() && e1.norm() > 0.0) {
    const Vec3 x = e1.normalized();
    const Vec3 y = nrm.normalized().cross(x);
    q1 = Vec2(e1.norm(), 0.0);
    q2 = Vec2(e2.dot(x), e2.dot(y));
  }
  Eigen::Matrix2d frame;
  frame.col(0) = q1;
  frame.col(1) = q2;
  return frame;
}

std::optional<FaceWork> TriangulateFace(const FaceStageInputs& in, FaceId fi, int* hint,
                                        Budget* budget) {
  const GraphFace& face = in.graph.faces[fi];
  const auto& d = in.located.deformed;
  FaceWork w(FaceFrame(in.ctx, face.corner), d[face.corner[0]], d[face.corner[1]],
             d[face.corner[2]]);
  if (budget != nullptr) w.tri.SetStop([budget] { return budget->OutOfTime(); });
  size_t inserted = 0;
  std::array<std::vector<int>, 3> side_ids;
  if (!SplitSides(in, face, &w, &side_ids, budget, &inserted)) return std::nullopt;
  const FaceMarks& marks = in.marking.faces[fi];
  std::vector<int> point_ids;
  if (!InsertFacePoints(in, face, marks, &w, hint, budget, &inserted, &point_ids)) {
    return std::nullopt;
  }
  if (marks.large && !ConstrainChords(in, fi, point_ids, side_ids, &w, budget, &inserted)) {
    return std::nullopt;
  }
  return w;
}

}  // namespace surfdeform::subdivision
