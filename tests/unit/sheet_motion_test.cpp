// The rigid motion between two flat sheets (engine/sheet_motion.hpp).
#include "engine/flatten/sheet_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/flatten/flatten.hpp"
#include "engine/surface/surface_spec.hpp"
#include "support/surface_file.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

TEST(SheetMotion, FindsAGivenMotionExactly) {
  std::vector<Vec2> from, to;
  const SheetMotion given{0.3, Vec2(1.5, -2.0), 0.0};
  for (int j = 0; j < 5; ++j) {
    for (int i = 0; i < 7; ++i) {
      from.emplace_back(i * 0.7, j * 1.1 + 0.1 * i * i);
      to.push_back(given.Apply(from.back()));
    }
  }
  auto m = BestSheetMotion(from, to);
  ASSERT_TRUE(m.ok());
  EXPECT_NEAR(m->angle, 0.3, 1e-12);
  EXPECT_NEAR((m->translation - given.translation).norm(), 0.0, 1e-12);
  EXPECT_NEAR(m->rms, 0.0, 1e-12);
  // A mirror image is no rotation: it is fitted as well as a rotation can.
  std::vector<Vec2> mirrored;
  for (const Vec2& p : from) mirrored.emplace_back(p.x(), -p.y());
  auto r = BestSheetMotion(from, mirrored);
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r->rms, 0.5);
  EXPECT_EQ(BestSheetMotion(from, std::span<const Vec2>(to).first(3)).status().code(),
            ErrorCode::kInvalidArgument);
}

// An edit of Figure 10 near the corner that fixes the canonical frame turns
// and shifts the whole sheet: the motion takes most of the difference (what
// is left is the sheet's own change).
TEST(SheetMotion, TakesMostOfAnEditsChangeOfTheSheet) {
  BezierSpec spec = testing::LoadBezierFile(testing::DataPath("figure10.json"));
  auto before = FlattenSurface(*testing::MakeValid(SurfaceSpec(spec)), {16, 16});
  spec.control_points[5].z() += 0.5;  // 5% of the patch
  auto after = FlattenSurface(*testing::MakeValid(SurfaceSpec(spec)), {16, 16});
  ASSERT_TRUE(before.ok() && after.ok());
  double raw = 0.0;
  for (size_t k = 0; k < before->flat.size(); ++k) {
    raw = std::max(raw, (before->flat[k] - after->flat[k]).norm());
  }
  auto m = BestSheetMotion(before->flat, after->flat);
  ASSERT_TRUE(m.ok());
  double left = 0.0;
  for (size_t k = 0; k < before->flat.size(); ++k) {
    left = std::max(left, (m->Apply(before->flat[k]) - after->flat[k]).norm());
  }
  // Measured through the API: 7.0e-3 of the diagonal raw, 1.7e-3 after the
  // motion (0.4 degrees).
  EXPECT_LT(left, 0.35 * raw);
  EXPECT_GT(std::abs(m->angle), 1e-3);
}

}  // namespace
}  // namespace surfdeform
