// A live edit's solve started ahead along the edit before it
// (engine/sheet_trend.hpp).
#include "engine/flatten/sheet_trend.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/flatten/flatten.hpp"
#include "engine/surface/surface_spec.hpp"
#include "support/surface_file.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

TEST(SheetTrend, TheStepIsHowMuchOfTheTrendTheSamplesRepeat) {
  SheetTrend t;
  t.points = {Vec3(1, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 0)};
  t.flat = {Vec2(1, 0), Vec2(0, 1), Vec2(0, 0)};
  const std::vector<Vec3> from = {Vec3(5, 5, 5), Vec3(1, 1, 1), Vec3(0, 0, 1)};
  auto moved = [&](double s, const Vec3& across) {
    std::vector<Vec3> now;
    for (size_t k = 0; k < from.size(); ++k) now.push_back(from[k] + s * t.points[k] + across);
    return now;
  };
  EXPECT_NEAR(TrendStep(t, from, moved(0.5, Vec3::Zero())), 0.5, 1e-15);
  EXPECT_NEAR(TrendStep(t, from, moved(-1.0, Vec3::Zero())), -1.0, 1e-15);  // turned back
  EXPECT_EQ(TrendStep(t, from, moved(3.0, Vec3::Zero())), 2.0);             // no further than 2
  EXPECT_EQ(TrendStep(t, from, moved(-3.0, Vec3::Zero())), -2.0);
  // A move across the trend (the samples' part along it is zero).
  EXPECT_NEAR(TrendStep(t, from, moved(0.0, Vec3(0, 0, 1))), 0.0, 1e-15);
  EXPECT_EQ(TrendStep(t, std::span<const Vec3>(from).first(2), moved(1.0, Vec3::Zero())), 0.0);
  EXPECT_EQ(TrendStep(SheetTrend{}, from, from), 0.0);
  const std::vector<Vec2> flat = {Vec2(0, 0), Vec2(1, 1), Vec2(2, 2)};
  const std::vector<Vec2> ahead = Extrapolated(flat, t, 0.5);
  EXPECT_EQ(ahead[0], Vec2(0.5, 0));
  EXPECT_EQ(ahead[1], Vec2(1, 1.5));
  EXPECT_EQ(ahead[2], Vec2(2, 2));
}

// Figure 10's control point 5 raised by 1% of the patch per edit, as a
// person drags it: the third edit, started ahead along the second's change,
// takes fewer iterations than started from the second's sheet as it is, at
// the same stress as a cold flattening (the live edits' bound, 1e-6). An edit
// going back starts behind (a negative step), and one of another control
// point across the first's trend starts from the sheet as it is.
TEST(SheetTrend, AnEditStartedAheadAlongTheLastTakesFewerIterations) {
  const BezierSpec base = testing::LoadBezierFile(testing::DataPath("figure10.json"));
  auto surface = [&](double lift5, double lift10) {
    BezierSpec b = base;
    b.control_points[5].z() += lift5;
    b.control_points[10].x() += lift10;
    return testing::MakeValid(SurfaceSpec(b));
  };
  FlattenOptions o;
  o.threads = 1;
  Flattener f(o);
  const SamplingOptions grid{16, 16};
  auto s0 = surface(0.0, 0.0), s1 = surface(0.1, 0.0), s2 = surface(0.2, 0.0);
  auto a = f.Flatten(*s0, grid);
  ASSERT_TRUE(a.ok());
  auto b = f.Flatten(*s1, grid, &*a);
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b->quality.extrapolated, 0.0);
  const SheetTrend trend = TrendBetween(*a, *b);
  ASSERT_EQ(trend.flat.size(), 256u);
  auto plain = f.Flatten(*s2, grid, &*b);
  auto ahead = f.Flatten(*s2, grid, &*b, nullptr, nullptr, &trend);
  auto cold = FlattenSurface(*s2, grid, o);
  ASSERT_TRUE(plain.ok() && ahead.ok() && cold.ok());
  EXPECT_EQ(plain->quality.extrapolated, 0.0);
  // The samples are linear in the control points: the same raise twice is
  // a step of exactly 1.
  EXPECT_NEAR(ahead->quality.extrapolated, 1.0, 1e-9);
  // Measured: 11 iterations from the sheet as it is, 4 started ahead.
  EXPECT_LE(ahead->quality.iterations, plain->quality.iterations - 4) << plain->quality.iterations;
  EXPECT_NEAR(ahead->quality.stress, cold->quality.stress, 1e-6 * cold->quality.stress);
  // Going back half way from the second edit: half a step behind.
  auto back = f.Flatten(*surface(0.05, 0.0), grid, &*b, nullptr, nullptr, &trend);
  ASSERT_TRUE(back.ok());
  EXPECT_NEAR(back->quality.extrapolated, -0.5, 1e-9);
  // Another control point moved sideways: little of the trend repeated.
  auto across = f.Flatten(*surface(0.1, 0.1), grid, &*b, nullptr, nullptr, &trend);
  ASSERT_TRUE(across.ok());
  EXPECT_LT(std::abs(across->quality.extrapolated), 0.2);
}

// Sheets of other grids, or periodic ones, have no trend between them.
TEST(SheetTrend, NoTrendBetweenSheetsOfAnotherGridOrPeriodic) {
  FlatSheet a, b;
  a.nu = b.nu = 2;
  a.nv = b.nv = 2;
  a.points = b.points = std::vector<Vec3>(4, Vec3::Zero());
  a.flat = b.flat = std::vector<Vec2>(4, Vec2::Zero());
  EXPECT_FALSE(TrendBetween(a, b).empty());
  FlatSheet other = b;
  other.nu = 4;
  other.nv = 1;
  EXPECT_TRUE(TrendBetween(a, other).empty());
  FlatSheet closed = b;
  closed.period_u = Vec2(1, 0);
  EXPECT_TRUE(TrendBetween(a, closed).empty());
}

}  // namespace
}  // namespace surfdeform
