// Quality measures and the canonical frame, on hand-made layouts.
#include <gtest/gtest.h>

#include "engine/flatten/flatten_solvers.hpp"

namespace surfdeform::internal {
namespace {

// A 3x3 grid of unit cells with exact distances for a flat unit grid.
SurfaceDistances UnitGrid() {
  SurfaceDistances d;
  d.nu = d.nv = 3;
  d.range = 3;
  for (int a = 0; a < 9; ++a) {
    for (int b = a + 1; b < 9; ++b) {
      GridEdge e;
      e.i = a;
      e.j = b;
      e.di = b % 3 - a % 3;
      e.dj = b / 3 - a / 3;
      e.ring = std::max(std::abs(e.di), std::abs(e.dj));
      e.d = std::hypot(e.di, e.dj);
      d.edges.push_back(e);
    }
  }
  d.cell_areas.assign(4, 1.0);
  return d;
}

std::vector<Vec2> UnitLayout() {
  std::vector<Vec2> x;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) x.emplace_back(i, j);
  return x;
}

TEST(FlattenQuality, ExactLayoutHasNoStress) {
  FlattenQuality q;
  MeasureQuality(UnitGrid(), UnitLayout(), &q);
  EXPECT_EQ(q.stress, 0.0);
  EXPECT_EQ(q.max_edge_error, 0.0);
  EXPECT_EQ(q.area_ratio_min, 1.0);
  EXPECT_EQ(q.area_ratio_max, 1.0);
  EXPECT_EQ(q.folded_cells, 0);
}

TEST(FlattenQuality, StretchedLayoutIsMeasured) {
  std::vector<Vec2> x = UnitLayout();
  for (Vec2& p : x) p.x() *= 1.1;
  FlattenQuality q;
  MeasureQuality(UnitGrid(), x, &q);
  EXPECT_NEAR(q.max_edge_error, 0.1, 1e-12);
  EXPECT_NEAR(q.area_ratio_min, 1.1, 1e-12);
  EXPECT_GT(q.stress, 0.01);
}

TEST(FlattenQuality, FoldedAndNonConvexCellsAreCounted) {
  std::vector<Vec2> x = UnitLayout();
  x[4] = Vec2(2.2, 2.3);  // the centre sample jumps past the far corner
  FlattenQuality q;
  MeasureQuality(UnitGrid(), x, &q);
  EXPECT_EQ(q.folded_cells, 3);  // the cell towards which it moved stays a convex kite
  x = UnitLayout();
  x[4] = Vec2(1.0, 0.4);  // squashes the lower cells, stretches the upper ones
  MeasureQuality(UnitGrid(), x, &q);
  EXPECT_EQ(q.folded_cells, 0);  // all four cells stay convex
  x[4] = Vec2(1.0, -0.2);        // below the bottom row: the lower cells turn inside out
  MeasureQuality(UnitGrid(), x, &q);
  EXPECT_EQ(q.folded_cells, 2);
}

TEST(FlattenQuality, CanonicalizeMovesTurnsAndMirrors) {
  std::vector<Vec2> x = UnitLayout();
  // Rotate by 30 degrees, shift, and mirror.
  for (Vec2& p : x) {
    const Vec2 r(std::cos(0.5) * p.x() - std::sin(0.5) * p.y(),
                 std::sin(0.5) * p.x() + std::cos(0.5) * p.y());
    p = Vec2(r.x() + 4, -(r.y() - 2));
  }
  Canonicalize(3, 3, &x);
  const std::vector<Vec2> expected = UnitLayout();
  for (size_t k = 0; k < x.size(); ++k) EXPECT_LT((x[k] - expected[k]).norm(), 1e-12);
}

TEST(FlattenQuality, MajorizationSolvesTheUnitGridFromANoisyStart) {
  const SurfaceDistances d = UnitGrid();
  std::vector<Vec2> x = UnitLayout();
  for (int k = 0; k < 9; ++k) x[k] += Vec2(0.1 * std::sin(3.0 * k), 0.1 * std::cos(5.0 * k));
  auto factor = FactorLaplacian(3, 3, 3);
  const SolveStats stats = SolveMajorization(*factor, d.edges, 1e-14, 500, 1, &x);
  EXPECT_TRUE(stats.converged);
  EXPECT_LT(Stress(d.edges, x), 1e-18);
}

TEST(FlattenQuality, SpectralLaplacianSolvesTheGraphLaplacian) {
  // Compare with an explicit dense Laplacian of the range-2 graph on a 5x4 grid.
  const int nu = 5, nv = 4, r = 2, n = nu * nv;
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(n, n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      if (a != b && std::abs(a % nu - b % nu) <= r && std::abs(a / nu - b / nu) <= r) {
        l(a, b) = -1;
        l(a, a) += 1;
      }
  Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(n, -1, 2).array().sin();
  x_true.array() -= x_true.mean();
  Eigen::VectorXd rhs = l * x_true;
  Eigen::MatrixXd b(nu, 2 * nv);
  b.leftCols(nv) = Eigen::Map<Eigen::MatrixXd>(rhs.data(), nu, nv);
  b.rightCols(nv) = -2.0 * b.leftCols(nv);
  auto f = FactorLaplacian(nu, nv, r);
  f->Solve(b, 1);
  const Eigen::VectorXd got_x = Eigen::Map<Eigen::VectorXd>(b.data(), n);
  const Eigen::VectorXd got_y = Eigen::Map<Eigen::VectorXd>(b.data() + n, n);
  EXPECT_LT((got_x.array() - got_x.mean() - x_true.array()).abs().maxCoeff(), 1e-12);
  EXPECT_LT((got_y.array() - got_y.mean() + 2.0 * x_true.array()).abs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace surfdeform::internal
