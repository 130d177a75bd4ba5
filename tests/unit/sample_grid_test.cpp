#include "engine/surface/sample_grid.hpp"

#include <gtest/gtest.h>

#include "engine/surface/surface_spec.hpp"

namespace surfdeform {
namespace {

TEST(SampleGrid, SamplesUFastestOnTheUnitSquare) {
  auto s = MakeSurface(CylinderSpec{1.0, 2.0, 90.0, {}});
  ASSERT_TRUE(s.ok());
  auto g = SampleSurface(**s, {3, 5});
  ASSERT_TRUE(g.ok()) << g.status().ToString();
  EXPECT_EQ(g->points.size(), 15u);
  EXPECT_LT((g->points[g->index(2, 0)] - (*s)->Position(1.0, 0.0)).norm(), 1e-15);
  EXPECT_LT((g->points[g->index(1, 4)] - (*s)->Position(0.5, 1.0)).norm(), 1e-15);
  EXPECT_NEAR(g->normals[g->index(1, 2)].norm(), 1.0, 1e-15);
}

TEST(SampleGrid, RejectsSizesOutsideTheLimits) {
  auto s = MakeSurface(WaveSpec{});
  ASSERT_TRUE(s.ok());
  for (SamplingOptions o : {SamplingOptions{1, 16}, SamplingOptions{16, 513}}) {
    auto g = SampleSurface(**s, o);
    ASSERT_FALSE(g.ok());
    EXPECT_EQ(g.status().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(g.status().message().find("2 to 512"), std::string::npos);
  }
}

TEST(SampleGrid, APoleHasNoNormal) {
  auto s = MakeSurface(SphereSpec{1.0, 0, 90, 0, 90, {}});  // reaches the north pole
  ASSERT_TRUE(s.ok());
  auto g = SampleSurface(**s, {8, 8});
  ASSERT_FALSE(g.ok());
  EXPECT_EQ(g.status().code(), ErrorCode::kDegenerate);
  EXPECT_NE(g.status().message().find("normal vanishes"), std::string::npos);
  EXPECT_NE(g.status().message().find("(0, 7)"), std::string::npos) << g.status().message();
}

TEST(SampleGrid, AConeApexHasNoNormal) {
  auto s = MakeSurface(ConeSpec{1.0, 0.0, 1.0, 120.0, {}});
  ASSERT_TRUE(s.ok());
  auto g = SampleSurface(**s, {4, 4});
  ASSERT_FALSE(g.ok());
  EXPECT_EQ(g.status().code(), ErrorCode::kDegenerate);
}

TEST(SampleGrid, CollapsedControlRowHasNoNormal) {
  BezierSpec b;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) b.control_points.emplace_back(j == 0 ? 0.0 : i, j, 0.0);
  auto s = MakeSurface(b);  // the v = 0 edge collapses to a point
  ASSERT_TRUE(s.ok());
  auto g = SampleSurface(**s, {5, 5});
  ASSERT_FALSE(g.ok());
  EXPECT_EQ(g.status().code(), ErrorCode::kDegenerate);
}

}  // namespace
}  // namespace surfdeform
