#include "engine/subdivision/face_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <queue>
#include <tuple>

#include "engine/common/parallel.hpp"
#include "engine/subdivision/triangle_deviation.hpp"

namespace surfdeform::subdivision {
namespace {

// True when the face can stay as it is: nothing on its sides, no kept face
// point, and its estimate or its centroid within the tolerance. Fills the
// tally either way when it has nothing to add.
bool KeepsItsShape(const FaceStageInputs& in, FaceId fi, double edge_dev, double edge_estimate,
                   FaceOutput* out, int* hint) {
  const Context& ctx = in.ctx;
  const GraphFace& face = in.graph.faces[fi];
  const auto& cell = in.located.cell;
  CellTerms terms;
  if (in.estimates.Terms(cell[face.corner[0]], cell[face.corner[1]], cell[face.corner[2]],
                         &terms)) {
    const FaceExtent x = ExtentOf(ctx, face.corner);
    const double estimate = EstimateOf(terms, std::sqrt(x.longest2), x.dh, x.h);
    if (ctx.Skippable(estimate)) {
      out->tally.max_estimate = std::max(estimate, edge_estimate);
      out->tally.max_dev = edge_dev;
      return true;
    }
  }
  const auto& d = in.located.deformed;
  const Vec3 fc = ctx.Deformed(ctx.InTriangle(face.corner, 1.0 / 3, 1.0 / 3), hint);
  const double dev =
      (fc - (d[face.corner[0]] + d[face.corner[1]] + d[face.corner[2]]) / 3.0).norm();
  out->tally.measured = 1;
  out->tally.max_dev = std::max(dev, edge_dev);
  out->tally.max_estimate = edge_estimate;
  return !ctx.refine || dev <= kFaceShare * ctx.tolerance;
}

// True when triangle t lies beside a side of the face so thinly (its height
// under 1/1000 of that side) that splitting it further cannot help.
bool Sliver(const FaceTriangulation& tri, int t) {
  const FaceTriangulation::Triangle& tr = tri.triangles()[t];
  const std::vector<Vec2>& pts = tri.points();
  for (int k = 0; k < 3; ++k) {
    if (!tri.OnOutline(t, k)) continue;
    const Vec2 a = pts[tr.v[(k + 1) % 3]], b = pts[tr.v[(k + 2) % 3]];
    const Vec2 ab = b - a, ac = pts[tr.v[k]] - a;
    if (std::abs(Cross2(ab, ac)) < 1e-3 * ab.squaredNorm()) return true;
  }
  return false;
}

// True when triangle t has (next to) no area: its corners on one line, its
// height under 1e-6 of its longest side. Its samples all lie on that line, so
// a split only adds points on it (each split making more such triangles) and
// never reaches the deviation beside it. Such triangles come of points
// inserted on a chord that lies along a side of the face.
bool Flat(const FaceTriangulation& tri, int t) {
  const FaceTriangulation::Triangle& tr = tri.triangles()[t];
  const std::vector<Vec2>& pts = tri.points();
  const Vec2 a = pts[tr.v[0]], b = pts[tr.v[1]], c = pts[tr.v[2]];
  const double longest2 =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  // twice the area < 1e-6 * longest^2: height < 1e-6 * longest
  return std::abs(Cross2(b - a, c - a)) < 1e-6 * longest2;
}

// Splits triangle t: the interior edge that strays most at its middle, or
// the longest when none strays (the deviation is inside), or the centroid of
// a triangle that is the whole face. False when a split cannot help.
bool SplitWorst(const Context& ctx, const GraphFace& face, double target, int t, FaceWork* w,
                int* hint) {
  FaceTriangulation& tri = w->tri;
  const FaceTriangulation::Triangle tr = tri.triangles()[t];
  const std::vector<Vec2>& pts = tri.points();
  int best = -1;
  double best_len = 0.0, best_dev = 0.0, longest = 0.0;
  int longest_k = -1;
  for (int k = 0; k < 3; ++k) {
    if (tri.OnOutline(t, k)) continue;
    const int a = tr.v[(k + 1) % 3], b = tr.v[(k + 2) % 3];
    const double len = (pts[a] - pts[b]).norm();
    if (len > longest) {
      longest = len;
      longest_k = k;
    }
    const Vec2 l = w->Bary(0.5 * (pts[a] + pts[b]));
    const double dev = (ctx.Deformed(ctx.InTriangle(face.corner, l.x(), l.y()), hint) -
                        0.5 * (w->fval[a] + w->fval[b]))
                           .norm();
    if (dev > best_dev) {
      best_dev = dev;
      best = k;
      best_len = len;
    }
  }
  if (best_dev <= 0.25 * target) {
    best = longest_k;
    best_len = longest;
  }
  if (best < 0) {
    tri.Insert((pts[tr.v[0]] + pts[tr.v[1]] + pts[tr.v[2]]) / 3.0);
    return true;
  }
  if (best_len < 1e-6 * tri.size()) return false;  // as fine as it gets
  if (Sliver(tri, t) || Flat(tri, t)) return false;
  tri.SplitInteriorEdge(t, best);
  return true;
}

// Refines the re-triangulated face until every triangle is within
// kFaceShare of the tolerance (or the budget is spent).
void RefineToTolerance(const Context& ctx, const GraphFace& face, FaceWork* w,
                       TriangleDeviation* deviation, Budget* budget, FaceOutput* out, int* hint) {
  const double target = kFaceShare * ctx.tolerance;
  FaceTriangulation& tri = w->tri;
  using Item = std::tuple<double, int, uint32_t>;
  std::priority_queue<Item> queue;
  for (size_t t = 0; t < tri.triangles().size(); ++t) {
    const double d = (*deviation)(static_cast<int>(t), hint);
    if (d > target) queue.push({d, static_cast<int>(t), tri.triangles()[t].stamp});
  }
  tri.TakeTouched();
  while (!queue.empty() && !budget->OverLimit() && !budget->OutOfTime()) {
    const auto [priority, t, stamp] = queue.top();
    queue.pop();
    if (tri.triangles()[t].stamp != stamp) continue;
    const size_t before = w->fval.size();
    if (!SplitWorst(ctx, face, target, t, w, hint)) continue;
    for (size_t id = before; id < tri.points().size(); ++id) {
      const Vec2 l = w->Bary(tri.points()[id]);
      w->Add({LocalPoint::Kind::kInside, 0, 0, l.x(), l.y()},
             ctx.Deformed(ctx.InTriangle(face.corner, l.x(), l.y()), hint));
      ++out->tally.refinement;
      budget->AddPoint();
    }
    for (int u : tri.TakeTouched()) {
      const double du = (*deviation)(u, hint);
      if (du > target) queue.push({du, u, tri.triangles()[u].stamp});
    }
  }
}

}  // namespace

FaceOutput RefineFace(const FaceStageInputs& in, FaceId fi, Budget* budget, int* hint) {
  FaceOutput out;
  const GraphFace& face = in.graph.faces[fi];
  if (face.degenerate) return out;
  bool on_sides = false;
  double edge_dev = 0.0, edge_estimate = 0.0;
  for (int k = 0; k < 3; ++k) {
    const RefinedEdge& e = in.edges[face.edge[k]];
    on_sides = on_sides || !e.kept_t.empty();
    edge_dev = std::max(edge_dev, e.tally.max_dev);
    edge_estimate = std::max(edge_estimate, e.tally.max_estimate);
  }
  for (const FacePoint& p : in.marking.faces[fi].points) out.face_points_kept += p.kept ? 1 : 0;
  if (!on_sides && out.face_points_kept == 0 &&
      KeepsItsShape(in, fi, edge_dev, edge_estimate, &out, hint)) {
    return out;
  }
  std::optional<FaceWork> work = TriangulateFace(in, fi, hint, budget);
  if (!work) {
    out.failed = !budget->OutOfTime();  // out of time: the request fails with that
    return out;
  }
  TriangleDeviation deviation(in.ctx, face.corner, *work, &out.tally);
  if (in.ctx.refine) RefineToTolerance(in.ctx, face, &*work, &deviation, budget, &out, hint);
  // Past a budget the request fails: measuring what was refined so far (the
  // whole face again, millions of triangles) would be work for nothing.
  if (budget->OverLimit() || budget->OutOfTime()) return out;
  out.tally.max_dev = edge_dev;
  out.tally.max_estimate = edge_estimate;
  const auto& tris = work->tri.triangles();
  out.triangles.reserve(tris.size());
  for (size_t t = 0; t < tris.size(); ++t) {
    out.tally.max_dev = std::max(out.tally.max_dev, deviation(static_cast<int>(t), hint));
    out.triangles.push_back({tris[t].v[0], tris[t].v[1], tris[t].v[2]});
  }
  out.points = std::move(work->local);
  return out;
}

IdVector<FaceId, FaceOutput> RefineFaces(const FaceStageInputs& in, Budget* budget) {
  IdVector<FaceId, FaceOutput> out(in.graph.faces.size());
  ParallelChunks(static_cast<int>(in.graph.faces.size()), in.ctx.threads,
                 [&](int, int begin, int end) {
                   int hint = -1;
                   for (int f = begin; f < end && !budget->OutOfTime(); ++f) {
                     out[FaceId(f)] = RefineFace(in, FaceId(f), budget, &hint);
                   }
                 });
  return out;
}

}  // namespace surfdeform::subdivision
