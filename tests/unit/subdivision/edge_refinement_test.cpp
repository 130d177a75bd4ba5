// Subdivision stage: each edge's final points.
#include "engine/subdivision/edge_refinement.hpp"

#include <gtest/gtest.h>

#include "stage_test_util.hpp"

namespace surfdeform::subdivision {
namespace {

struct Edges {
  std::unique_ptr<testing::StageInputs> in;
  std::unique_ptr<testing::StagesThroughFaces> s;
};

Edges RunEdges(testing::Target target, Mesh mesh, const SubdivisionOptions& options) {
  Edges e;
  e.in = testing::MakeStageInputs(std::move(target), std::move(mesh), options);
  e.s = testing::RunThroughFaces(*e.in);
  return e;
}

// The largest distance, at 200 points along the edge, between the exact
// deformation and the polyline through the edge's ends and final points.
double DenseEdgeDeviation(const Context& ctx, const GraphEdge& edge, const RefinedEdge& r,
                          const LocatedVertices& l) {
  std::vector<double> t = {0.0};
  std::vector<Vec3> f = {l.deformed[edge.v0]};
  t.insert(t.end(), r.kept_t.begin(), r.kept_t.end());
  f.insert(f.end(), r.kept_f.begin(), r.kept_f.end());
  t.push_back(1.0);
  f.push_back(l.deformed[edge.v1]);
  double worst = 0.0;
  int hint = -1;
  for (int q = 1; q < 200; ++q) {
    const double at = q / 200.0;
    const size_t k = std::upper_bound(t.begin(), t.end(), at) - t.begin() - 1;
    const double w = (at - t[k]) / (t[k + 1] - t[k]);
    const Vec3 exact = ctx.Deformed(ctx.Between(edge.v0, edge.v1, at), &hint);
    worst = std::max(worst, (exact - ((1.0 - w) * f[k] + w * f[k + 1])).norm());
  }
  return worst;
}

TEST(EdgeRefinement, EveryEdgeFollowsTheSurfaceWithinTheTolerance) {
  for (double tolerance : {1e-2, 1e-3, 1e-4}) {
    const Edges e = RunEdges(testing::Cylinder(1.0), testing::ThinPlate(2.4, 1.6, 0.1),
                             testing::Tolerance(tolerance));
    const Context& ctx = *e.in->ctx;
    size_t refined = 0;
    for (size_t k = 0; k < e.s->graph.edges.size(); ++k) {
      const EdgeId id(k);
      const RefinedEdge& r = e.s->edges[id];
      refined += r.tally.refinement;
      EXPECT_LE(r.tally.max_dev, kEdgeShare * tolerance);
      EXPECT_LE(DenseEdgeDeviation(ctx, e.s->graph.edges[id], r, e.s->located), tolerance)
          << tolerance << " edge " << k;
      ASSERT_EQ(r.kept_t.size(), r.kept_f.size());
      for (size_t q = 0; q < r.kept_t.size(); ++q) {
        EXPECT_GT(r.kept_t[q], q == 0 ? 0.0 : r.kept_t[q - 1]);
        EXPECT_LT(r.kept_t[q], 1.0);
        int hint = -1;
        const GraphEdge& g = e.s->graph.edges[id];
        EXPECT_EQ(r.kept_f[q], ctx.Deformed(ctx.Between(g.v0, g.v1, r.kept_t[q]), &hint));
      }
    }
    // Cells of side ~0.21 on the unit cylinder: pieces between grid lines
    // stray ~0.0055, so below that the edges are bisected.
    if (tolerance < 5e-3) {
      EXPECT_GT(refined, 0u) << tolerance;
    }
  }
}

TEST(EdgeRefinement, MarkedCrossingsAreKeptAndUniformAddsNothingElse) {
  SubdivisionOptions uniform;
  uniform.mode = SubdivisionMode::kUniform;
  for (const SubdivisionOptions& o : {testing::Tolerance(1e-3), uniform}) {
    const Edges e = RunEdges(testing::Figure(10, 10), testing::ThinPlate(1.0, 1.0, 0.02), o);
    for (size_t k = 0; k < e.s->graph.edges.size(); ++k) {
      const RefinedEdge& r = e.s->edges[EdgeId(k)];
      std::vector<double> marked;
      for (const EdgePoint& p : e.s->marking.edges[EdgeId(k)].points) {
        if (p.marked) marked.push_back(p.crossing.t);
      }
      for (double t : marked) {
        EXPECT_TRUE(std::binary_search(r.kept_t.begin(), r.kept_t.end(), t)) << k;
      }
      if (o.mode == SubdivisionMode::kUniform) {
        EXPECT_EQ(r.kept_t, marked) << k;
        EXPECT_EQ(r.tally.refinement, 0u);
      }
    }
  }
}

TEST(EdgeRefinement, TheSizeBudgetStopsTheBisection) {
  SubdivisionOptions o = testing::Tolerance(1e-6);
  o.max_vertices = 20;
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0), testing::ThinPlate(2.4, 1.6, 0.1), o);
  const LocatedVertices l = in->Located();
  const CellEstimates est(*in->ctx, l.cell);
  const EdgeGraph g = BuildEdgeGraph(in->mesh);
  const GridMarking m = in->Marked(g, l, est);
  Budget budget(o, in->mesh.positions.size());
  const auto edges = RefineEdges(*in->ctx, g, m, l, est, &budget);
  EXPECT_TRUE(budget.OverLimit());
  size_t added = 0;
  for (const RefinedEdge& r : edges) added += r.tally.refinement;
  EXPECT_EQ(added, budget.added());
  EXPECT_LT(added, 20u + 2 * in->ctx->threads);  // stops within a split per thread
}

}  // namespace
}  // namespace surfdeform::subdivision
