// Subdivision stage: the terms of the deviation estimate, per cell.
#include "engine/subdivision/cell_estimates.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "engine/subdivision/vertex_location.hpp"
#include "stage_test_util.hpp"

namespace surfdeform::subdivision {
namespace {

TEST(CellEstimates, EstimateOfIsTwiceTheSagittaOfAStraightPiece) {
  CellTerms t;
  t.curvature = 0.5;
  EXPECT_DOUBLE_EQ(EstimateOf(t, 0.4, 0.0, 0.0), 2.0 * 0.5 * 0.4 * 0.4 / 8.0);
  // At height h the offset surface bends by k (1 + |h| k); a kink j adds j l / 4.
  t.kink = 0.1;
  EXPECT_DOUBLE_EQ(EstimateOf(t, 0.4, 0.0, 1.0), 2.0 * (0.5 * 1.5 * 0.16 / 8.0 + 0.1 * 0.4 / 4.0));
  // Where the normal's second derivative passes the curvature squared, the
  // offset surface bends by k + |h| bend.
  t.bend = 2.0;
  EXPECT_DOUBLE_EQ(EstimateOf(t, 0.4, 0.0, 1.0), 2.0 * (2.5 * 0.16 / 8.0 + 0.1 * 0.4 / 4.0));
}

TEST(CellEstimates, OnACylinderTheCurvatureIsOneOverTheRadiusAndNothingKinks) {
  auto in = testing::MakeStageInputs(
      testing::Cylinder(2.0), testing::FlatGrid(-1, -1, 2, 2, 8, 8, 0.0), testing::Tolerance(1e-3));
  const LocatedVertices l = in->Located();
  const CellEstimates e(*in->ctx, l.cell);
  int computed = 0;
  for (int c = 0; c < in->ctx->grid.cell_count(); ++c) {
    const CellTerms& t = e.cell(c);
    if (t.curvature < 0) continue;
    ++computed;
    EXPECT_NEAR(t.curvature, 0.5, 1e-9) << c;
    // The normal turns at 1/r all round: its second derivative is 1/r^2 (the
    // finite difference over a cell: 2 sin(a/2)/a of it, a the cell's angle).
    EXPECT_NEAR(t.bend, 0.25, 0.01) << c;
    EXPECT_GT(t.min_side, 0.0);
    // The unrolled cylinder's cells are rectangles: no twist.
    EXPECT_LT(t.twist, 1e-9) << c;
  }
  EXPECT_GT(computed, 20);
  for (int s = 0; s < in->ctx->grid.side_count(); ++s) {
    EXPECT_LT(e.side_kink(s), 1e-5) << s;  // the closed-form map has no kinks
  }
}

// The largest second derivative, over the arc length, of the unit normal of
// the curve z = a sin(k x): central differences of the closed form.
double WaveNormalBend(double a, double k) {
  auto normal = [&](double x) -> Vec2 {
    const double slope = a * k * std::cos(k * x);
    return Vec2(-slope, 1.0) / std::hypot(slope, 1.0);
  };
  auto arc = [&](double x0, double x1) {  // the chord, over steps this short
    return std::hypot(x1 - x0, a * (std::sin(k * x1) - std::sin(k * x0)));
  };
  const double h = 1e-4;
  auto rate = [&](double x) -> Vec2 { return (normal(x + h) - normal(x - h)) / arc(x - h, x + h); };
  double best = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const double x = i * (2.0 * std::numbers::pi / k) / 2000;
    const Vec2 second = (rate(x + h) - rate(x - h)) / arc(x - h, x + h);
    best = std::max(best, second.norm());
  }
  return best;
}

// Along a short wave z = A sin(k x) the curvature changes fast: the normal's
// second derivative reaches about A k^3 where the curvature A k^2 sin(k x)
// passes zero, well past the curvature squared anywhere. A model 1.2 above
// the surface follows it: counting only the curvature squared, the estimate
// skipped pieces that strayed by 1.5 times the tolerance.
TEST(CellEstimates, OnAShortWaveTheNormalsSecondDerivativeIsCounted) {
  WaveSpec wave;
  wave.length = wave.width = 4.0;
  wave.amplitude = 0.02;
  wave.wavelength = 0.5;
  const double k = 2.0 * std::numbers::pi / wave.wavelength;
  auto in = testing::MakeStageInputs(testing::Flattened(wave, 64),
                                     testing::FlatGrid(-1.5, -1.5, 3, 3, 30, 30, 0.0),
                                     testing::Tolerance(1e-3));
  const LocatedVertices l = in->Located();
  const CellEstimates e(*in->ctx, l.cell);
  double bend = 0.0, curvature = 0.0;
  for (int c = 0; c < in->ctx->grid.cell_count(); ++c) {
    bend = std::max(bend, e.cell(c).bend);
    curvature = std::max(curvature, e.cell(c).curvature);
  }
  EXPECT_NEAR(curvature, wave.amplitude * k * k, 0.05 * wave.amplitude * k * k);
  // 35.1 here (A k^3 is 39.7; the slope A k = 0.25 slows the turning).
  const double exact = WaveNormalBend(wave.amplitude, k);
  EXPECT_NEAR(bend, exact, 0.05 * exact);
  EXPECT_GT(bend, 3.0 * curvature * curvature);
}

TEST(CellEstimates, OnlyCellsNearTheModelAreComputed) {
  PlacementOptions small;
  small.scale = 0.05;  // a model well inside one or two cells at the sheet's centre
  auto in =
      testing::MakeStageInputs(testing::Cylinder(1.0), testing::FlatGrid(-1, -1, 2, 2, 2, 2, 0.0),
                               testing::Tolerance(1e-3), small);
  const LocatedVertices l = in->Located();
  const CellEstimates e(*in->ctx, l.cell);
  int computed = 0;
  for (int c = 0; c < in->ctx->grid.cell_count(); ++c) computed += e.cell(c).curvature >= 0;
  EXPECT_GE(computed, 9);   // a cell and its neighbours
  EXPECT_LE(computed, 16);  // a 2 x 2 block and theirs
}

TEST(CellEstimates, TermsCoverOneCellOrOneTwoByTwoBlockOnly) {
  auto in = testing::MakeStageInputs(testing::Flattened(testing::BumpOnAPlane(0.4), 12),
                                     testing::FlatGrid(-1, -1, 2, 2, 20, 20, 0.0),
                                     testing::Tolerance(1e-3));
  const LocatedVertices l = in->Located();
  const CellEstimates e(*in->ctx, l.cell);
  const CellGrid& g = in->ctx->grid;
  CellTerms t;
  ASSERT_TRUE(e.Terms(g.Cell(5, 5), g.Cell(5, 5), g.Cell(5, 5), &t));
  EXPECT_EQ(t.curvature, e.cell(g.Cell(5, 5)).curvature);
  EXPECT_EQ(t.kink, 0.0);
  ASSERT_TRUE(e.Terms(g.Cell(5, 5), g.Cell(6, 5), g.Cell(6, 6), &t));
  double kappa = 0.0, side = kInf;
  for (int j = 5; j <= 6; ++j)
    for (int i = 5; i <= 6; ++i) {
      kappa = std::max(kappa, e.cell(g.Cell(i, j)).curvature);
      side = std::min(side, e.cell(g.Cell(i, j)).min_side);
    }
  EXPECT_EQ(t.curvature, kappa);
  EXPECT_EQ(t.min_side, side);
  // The kink is the largest of the four sides inside the block.
  const double inside =
      std::max({e.side_kink(g.SideAlongV(6, 5)), e.side_kink(g.SideAlongV(6, 6)),
                e.side_kink(g.SideAlongU(5, 6)), e.side_kink(g.SideAlongU(6, 6))});
  EXPECT_EQ(t.kink, inside);
  EXPECT_GT(inside, 0.0);  // a numerically flattened sheet's map kinks across its sides
  EXPECT_FALSE(e.Terms(g.Cell(5, 5), g.Cell(7, 5), g.Cell(5, 5), &t));
  EXPECT_FALSE(e.Terms(g.Cell(5, 5), -1, g.Cell(5, 5), &t));
}

}  // namespace
}  // namespace surfdeform::subdivision
