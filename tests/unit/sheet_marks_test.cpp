// Marks between sheet and surface: analytic cases (a plane maps to itself, a
// cylinder as its closed form), sheet -> surface -> sheet round trips to
// 1e-9, and polylines resampled to the tolerance.
#include "engine/sheet/sheet_marks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "support/surface_file.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

using testing::Flattened;
using testing::Target;
constexpr double kPi = std::numbers::pi;

// Points spread over the sheet's bounding box that lie on the sheet.
std::vector<Vec2> PointsOnTheSheet(const SheetMap& map, int count) {
  std::mt19937 rng(7);
  const Eigen::AlignedBox2d box = map.locator().bounds();
  std::uniform_real_distribution<double> x(box.min().x(), box.max().x());
  std::uniform_real_distribution<double> y(box.min().y(), box.max().y());
  std::vector<Vec2> out;
  SheetLocation loc;
  while (static_cast<int>(out.size()) < count) {
    const Vec2 p(x(rng), y(rng));
    if (map.locator().Locate(p, &loc)) out.push_back(p);
  }
  return out;
}

TEST(SheetMarks, APlaneMapsToItself) {
  BezierSpec plane;  // [0, 2]^2 at z = 0
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) plane.control_points.emplace_back(2.0 * i / 3, 2.0 * j / 3, 0.0);
  const Target t = Flattened(plane, 8);
  const SheetMap map(*t.surface, t.sheet);
  for (const Vec2& p : PointsOnTheSheet(map, 50)) {
    const SheetMark m = MarkAt(map, p);
    EXPECT_TRUE(m.on_sheet);
    EXPECT_LT((m.point - Vec3(p.x(), p.y(), 0)).norm(), 1e-9);
    EXPECT_LT((m.normal - Vec3::UnitZ()).norm(), 1e-9);
    EXPECT_LT((m.uv - p / 2).norm(), 1e-9);
  }
}

TEST(SheetMarks, ACylinderAsItsClosedForm) {
  const double radius = 2.0, height = 3.0;
  const Target t = Flattened(CylinderSpec{radius, height, 180.0, {}}, 16);
  const SheetMap map(*t.surface, t.sheet);
  // The sheet is [0, pi R] x [0, height]: (a, b) lands at angle a / R, z = b.
  for (const Vec2& p : PointsOnTheSheet(map, 50)) {
    const SheetMark m = MarkAt(map, p);
    const double theta = p.x() / radius;
    EXPECT_LT((m.point - Vec3(radius * std::cos(theta), radius * std::sin(theta), p.y())).norm(),
              1e-9);
    EXPECT_LT((m.normal - Vec3(std::cos(theta), std::sin(theta), 0)).norm(), 1e-9);
  }
  // Off the sheet: clamped to its border, and said so.
  const SheetMark off = MarkAt(map, Vec2(kPi * radius / 2, height + 1.0));
  EXPECT_FALSE(off.on_sheet);
  EXPECT_NEAR(off.point.z(), height, 1e-9);
  EXPECT_EQ(off.sheet, Vec2(kPi * radius / 2, height + 1.0));
}

// Sheet -> surface -> nearest surface point -> sheet, on a developable kind
// (closed-form unrolling) and on the paper's Bezier patch (cells).
TEST(SheetMarks, MapThenMapBackIsTheIdentity) {
  const Target cylinder = Flattened(CylinderSpec{2.0, 3.0, 180.0, {}}, 16);
  const Target patch = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  for (const Target* t : {&cylinder, &patch}) {
    const SheetMap map(*t->surface, t->sheet);
    for (const Vec2& p : PointsOnTheSheet(map, 200)) {
      const SheetMark there = MarkAt(map, p);
      const SheetMark back = MarkNearest(map, there.point);
      EXPECT_LT(back.distance, 1e-9);
      EXPECT_LT((back.uv - there.uv).norm(), 1e-9) << p.transpose();
      EXPECT_LT((back.sheet - p).norm(), 1e-9) << p.transpose();
      EXPECT_LT((back.normal - there.normal).norm(), 1e-9);
    }
  }
}

TEST(SheetMarks, NearestPointOffTheSurfaceIsAlongTheNormal) {
  const Target t = Flattened(CylinderSpec{2.0, 3.0, 180.0, {}}, 16);
  const SheetMap map(*t.surface, t.sheet);
  // 0.5 outside the cylinder at angle 60 degrees, z = 1: the nearest point is
  // on the cylinder straight in, 0.5 away.
  const double theta = kPi / 3;
  const SheetMark m = MarkNearest(map, Vec3(2.5 * std::cos(theta), 2.5 * std::sin(theta), 1.0));
  EXPECT_NEAR(m.distance, 0.5, 1e-9);
  EXPECT_LT((m.sheet - Vec2(2.0 * theta, 1.0)).norm(), 1e-9);
  // Beyond the surface's end (z = 3): its border, the domain is kept.
  const SheetMark end = MarkNearest(map, Vec3(2.0 * std::cos(theta), 2.0 * std::sin(theta), 4.0));
  EXPECT_NEAR(end.uv.y(), 1.0, 1e-12);
  EXPECT_NEAR(end.distance, 1.0, 1e-9);
}

TEST(SheetMarks, PolylinesAreResampledToTheTolerance) {
  const double radius = 2.0;
  const Target t = Flattened(CylinderSpec{radius, 3.0, 180.0, {}}, 16);
  const SheetMap map(*t.surface, t.sheet);
  // Around the cylinder (an arc on the surface), then up it (straight).
  const std::vector<Vec2> line = {{0.2, 1.0}, {kPi * radius - 0.2, 1.0}, {kPi * radius - 0.2, 2.5}};
  PolylineOptions o;
  o.tolerance = 1e-4;
  auto r = ResamplePolylines(map, {line}, o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const std::vector<SheetMark>& out = (*r)[0];
  // The given vertices are kept, in order; the added ones lie on the pieces.
  EXPECT_LT((out.front().sheet - line[0]).norm(), 1e-15);
  EXPECT_LT((out.back().sheet - line[2]).norm(), 1e-15);
  size_t corner = 0;
  for (size_t k = 0; k < out.size(); ++k) {
    if ((out[k].sheet - line[1]).norm() < 1e-12) corner = k;
  }
  ASSERT_GT(corner, 0u);
  // Every chord within the tolerance of the arc: its sagitta l^2 / (8 R).
  double longest = 0.0;
  for (size_t k = 0; k + 1 <= corner; ++k) {
    const double l = (out[k + 1].point - out[k].point).norm();
    EXPECT_LE(l * l / (8 * radius), o.tolerance * 1.0001) << k;
    EXPECT_NEAR(out[k].sheet.y(), 1.0, 1e-12);
    longest = std::max(longest, l);
  }
  // ... and not far more points than that needs (bisection: at most twice).
  const double arc = kPi * radius - 0.4;
  const double fewest = arc / std::sqrt(8 * radius * o.tolerance);
  EXPECT_GE(static_cast<double>(corner), fewest);
  EXPECT_LE(static_cast<double>(corner), 2.0 * fewest + 1);
  // Up the cylinder the image is straight: no point added.
  EXPECT_EQ(out.size(), corner + 2);
  // max_segment splits the straight part too.
  o.max_segment = 0.1;
  auto fine = ResamplePolylines(map, {line}, o);
  ASSERT_TRUE(fine.ok());
  for (size_t k = 0; k + 1 < (*fine)[0].size(); ++k) {
    EXPECT_LE(((*fine)[0][k + 1].sheet - (*fine)[0][k].sheet).norm(), 0.1 + 1e-12);
  }
  // Past the point budget: the limit and the count.
  o.max_points = 20;
  auto over = ResamplePolylines(map, {line}, o);
  ASSERT_FALSE(over.ok());
  EXPECT_EQ(over.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(over.status().limit(), 20.0);
  // One point is not a polyline.
  auto single = ResamplePolylines(map, {{Vec2(1, 1)}}, PolylineOptions{});
  ASSERT_FALSE(single.ok());
  EXPECT_EQ(single.status().field(), "polylines[0]");
}

}  // namespace
}  // namespace surfdeform
