#include "engine/flat_locator.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "engine/surface_spec.hpp"
#include "support/surface_file.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

FlatSheet Sheet(const SurfaceSpec& spec, int n) {
  auto s = testing::MakeValid(spec);
  auto r = FlattenSurface(*s, {n, n});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return std::move(r).value();
}

TEST(FlatLocator, InvertsEveryCellMapExactly) {
  const FlatSheet sheet = Sheet(testing::LoadBezierFile(testing::DataPath("figure10.json")), 12);
  FlatLocator locator(sheet);
  for (int j = 0; j < 11; ++j) {
    for (int i = 0; i < 11; ++i) {
      for (double s : {0.0, 0.13, 0.5, 0.91}) {
        for (double t : {0.07, 0.5, 1.0}) {
          const SheetLocation want{i, j, s, t};
          const Vec2 p = locator.FlatPoint(want);
          SheetLocation got;
          ASSERT_TRUE(locator.Locate(p, &got)) << i << "," << j << " " << s << "," << t;
          // A point on a shared edge may be reported by either cell: compare
          // the parameters, which agree there.
          EXPECT_LT((locator.Parameters(got) - locator.Parameters(want)).norm(), 1e-12);
        }
      }
    }
  }
}

TEST(FlatLocator, PointsOutsideAreNotLocatedAndMeasured) {
  const FlatSheet sheet = Sheet(CylinderSpec{1.0, 1.0, 90.0, {}}, 8);  // a rectangle from 0
  FlatLocator locator(sheet);
  SheetLocation l;
  const double width = 1.0 * std::numbers::pi / 2;
  EXPECT_FALSE(locator.Locate(Vec2(-0.1, 0.5), &l));
  EXPECT_FALSE(locator.Locate(Vec2(width + 0.2, 0.5), &l));
  double d;
  const SheetLocation q = locator.NearestOnBoundary(Vec2(width + 0.2, 0.5), &d);
  EXPECT_NEAR(d, 0.2, 1e-12);
  EXPECT_NEAR(locator.Parameters(q).x(), 1.0, 1e-12);
  EXPECT_NEAR(locator.Parameters(q).y(), 0.5, 1e-12);
}

}  // namespace
}  // namespace surfdeform
