#include "engine/subdivision/edge_refinement.hpp"

#include <algorithm>

#include "engine/common/parallel.hpp"

namespace surfdeform::subdivision {
namespace {

struct Span {
  double ta, tb;
  Vec3 fa, fb;
  int depth;
};

// The worst sample of a span of `edge`: at its quarter points (an S-shaped
// deviation, an inflection, is near zero at the middle) and at the grid
// crossings inside it that were not kept.
struct Worst {
  double dev = -1.0;
  double t = 0.0;
  Vec3 f = Vec3::Zero();
};
Worst WorstSample(const Context& ctx, const GraphEdge& edge, const EdgeMarks& marks, const Span& s,
                  Tally* tally, int* hint) {
  Worst worst;
  worst.t = 0.5 * (s.ta + s.tb);
  auto sample = [&](double t) {
    const Vec3 fm = ctx.Deformed(ctx.Between(edge.v0, edge.v1, t), hint);
    const double w = (t - s.ta) / (s.tb - s.ta);
    const double dev = (fm - ((1.0 - w) * s.fa + w * s.fb)).norm();
    ++tally->measured;
    if (dev > worst.dev) worst = {dev, t, fm};
  };
  for (double w : {0.25, 0.5, 0.75}) sample(s.ta + w * (s.tb - s.ta));
  const auto first =
      std::upper_bound(marks.points.begin(), marks.points.end(), s.ta,
                       [](double t, const EdgePoint& p) { return t < p.crossing.t; });
  for (auto it = first; it != marks.points.end() && it->crossing.t < s.tb; ++it) {
    if (!it->marked) sample(it->crossing.t);
  }
  return worst;
}

// Measures, and with a tolerance bisects, the piece from (prev_t, prev_f) to
// (next_t, next_f), appending the split points inside it to `out`.
void RefinePiece(const Context& ctx, const GraphEdge& edge, const EdgeMarks& marks, double prev_t,
                 const Vec3& prev_f, double next_t, const Vec3& next_f, Budget* budget,
                 std::vector<Span>* stack, RefinedEdge* out, int* hint) {
  const double length = (ctx.Placed(edge.v1) - ctx.Placed(edge.v0)).norm();
  stack->clear();
  stack->push_back({prev_t, next_t, prev_f, next_f, 0});
  // Depth first, left half last pushed: points come out in order. One edge
  // can take up to the output's limit of points (seconds): the time budget is
  // looked at every 64 pieces, and the request fails with it when spent.
  size_t pieces = 0;
  while (!stack->empty()) {
    if (++pieces % 64 == 0 && budget->OutOfTime()) return;
    const Span s = stack->back();
    stack->pop_back();
    const Worst worst = WorstSample(ctx, edge, marks, s, &out->tally, hint);
    const bool split = ctx.refine && worst.dev > kEdgeShare * ctx.tolerance &&
                       s.depth < kMaxBisections &&
                       (s.tb - s.ta) * length > 1e-9 * ctx.sheet_diagonal && !budget->OverLimit();
    if (!split) {
      out->tally.max_dev = std::max(out->tally.max_dev, worst.dev);
      if (s.tb < next_t) {  // a split point closes this span
        out->kept_t.push_back(s.tb);
        out->kept_f.push_back(s.fb);
      }
      continue;
    }
    ++out->tally.refinement;
    budget->AddPoint();
    stack->push_back({worst.t, s.tb, worst.f, s.fb, s.depth + 1});
    stack->push_back({s.ta, worst.t, s.fa, worst.f, s.depth + 1});
  }
}

RefinedEdge RefineEdge(const Context& ctx, const GraphEdge& edge, const EdgeMarks& marks,
                       const LocatedVertices& located, const CellEstimates& estimates,
                       Budget* budget, std::vector<Span>* stack, int* hint) {
  RefinedEdge out;
  std::vector<double> ts;
  for (const EdgePoint& p : marks.points) {
    if (p.marked) ts.push_back(p.crossing.t);
  }
  std::vector<Vec3> fs(ts.size());
  for (size_t q = 0; q < ts.size(); ++q)
    fs[q] = ctx.Deformed(ctx.Between(edge.v0, edge.v1, ts[q]), hint);
  CellTerms terms;
  if (ts.empty() && estimates.Terms(located.cell[edge.v0], located.cell[edge.v1],
                                    located.cell[edge.v1], &terms)) {
    const Vec3 d = ctx.Placed(edge.v1) - ctx.Placed(edge.v0);
    const double h = std::max(std::abs(ctx.Placed(edge.v0).z()), std::abs(ctx.Placed(edge.v1).z()));
    const double estimate = EstimateOf(terms, d.head<2>().norm(), d.z(), h);
    if (ctx.Skippable(estimate)) {
      out.tally.max_estimate = estimate;
      return out;
    }
  }
  Vec3 prev_f = located.deformed[edge.v0];
  double prev_t = 0.0;
  for (size_t q = 0; q <= ts.size(); ++q) {
    const double next_t = q < ts.size() ? ts[q] : 1.0;
    const Vec3 next_f = q < ts.size() ? fs[q] : located.deformed[edge.v1];
    RefinePiece(ctx, edge, marks, prev_t, prev_f, next_t, next_f, budget, stack, &out, hint);
    if (q < ts.size()) {
      out.kept_t.push_back(next_t);
      out.kept_f.push_back(next_f);
    }
    prev_t = next_t;
    prev_f = next_f;
  }
  return out;
}

}  // namespace

IdVector<EdgeId, RefinedEdge> RefineEdges(const Context& ctx, const EdgeGraph& graph,
                                          const GridMarking& marking,
                                          const LocatedVertices& located,
                                          const CellEstimates& estimates, Budget* budget) {
  IdVector<EdgeId, RefinedEdge> out(graph.edges.size());
  ParallelChunks(static_cast<int>(graph.edges.size()), ctx.threads, [&](int, int begin, int end) {
    int hint = -1;
    std::vector<Span> stack;
    for (int e = begin; e < end && !budget->OutOfTime(); ++e) {
      out[EdgeId(e)] = RefineEdge(ctx, graph.edges[EdgeId(e)], marking.edges[EdgeId(e)], located,
                                  estimates, budget, &stack, &hint);
    }
  });
  return out;
}

}  // namespace surfdeform::subdivision
