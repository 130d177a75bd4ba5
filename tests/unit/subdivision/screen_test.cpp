// Subdivision stage: the screen (a model that needs nothing).
#include "engine/subdivision/screen.hpp"

#include <gtest/gtest.h>

#include "stage_test_util.hpp"

namespace surfdeform::subdivision {
namespace {

ScreenResult ScreenOf(const testing::StageInputs& in) {
  const LocatedVertices l = in.Located();
  const CellEstimates e(*in.ctx, l.cell);
  return Screen(*in.ctx, l, e);
}

TEST(Screen, AModelFinerThanTheGridOnAGentleSurfacePasses) {
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0),
                                     testing::FlatGrid(-1, -1, 2, 2, 60, 60, 0.0), {});
  const ScreenResult s = ScreenOf(*in);
  EXPECT_TRUE(s.pass);
  EXPECT_LE(s.max_estimate, kSkipShare * in->ctx->tolerance);
  EXPECT_LE(s.max_deviation, kFaceShare * in->ctx->tolerance);
}

TEST(Screen, FacesLargerThanACellFail) {
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0), testing::ThinPlate(2, 1, 0.1), {});
  EXPECT_FALSE(ScreenOf(*in).pass);
}

TEST(Screen, ATighterToleranceThanTheFacesMeetFails) {
  auto in =
      testing::MakeStageInputs(testing::Cylinder(1.0), testing::FlatGrid(-1, -1, 2, 2, 60, 60, 0.0),
                               testing::Tolerance(1e-7));
  const ScreenResult s = ScreenOf(*in);
  EXPECT_FALSE(s.pass);
}

TEST(Screen, MeasuresWhereTheEstimateIsNotSmallEnough) {
  // An 80 x 80 grid fitted on the unit cylinder has sides of about 0.0225
  // and diagonals of 0.032: they stray about l^2 / 8 = 1.3e-4, which the
  // estimate (twice that) puts above half of a 2e-4 tolerance, so they are
  // measured; measured, they are within it, and the model passes.
  auto in =
      testing::MakeStageInputs(testing::Cylinder(1.0), testing::FlatGrid(-1, -1, 2, 2, 80, 80, 0.0),
                               testing::Tolerance(2e-4));
  const ScreenResult s = ScreenOf(*in);
  EXPECT_TRUE(s.pass);
  EXPECT_GT(s.measured_points, 0u);
  EXPECT_GT(s.max_deviation, 0.0);
}

TEST(Screen, WithoutAToleranceNothingPasses) {
  SubdivisionOptions eps;
  eps.epsilon = 0.5;  // curvature only: nothing to screen against
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0),
                                     testing::FlatGrid(-1, -1, 2, 2, 60, 60, 0.0), eps);
  EXPECT_FALSE(in->ctx->refine);
  EXPECT_FALSE(ScreenOf(*in).pass);
}

}  // namespace
}  // namespace surfdeform::subdivision
