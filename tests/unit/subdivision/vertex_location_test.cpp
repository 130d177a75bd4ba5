// Subdivision stage: where each input vertex lands.
#include "engine/subdivision/vertex_location.hpp"

#include <gtest/gtest.h>

#include "stage_test_util.hpp"

namespace surfdeform::subdivision {
namespace {

TEST(VertexLocation, PositionsAreTheDeformationsAndCellsHoldTheVertices) {
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0),
                                     testing::FlatGrid(-1, -1, 2, 2, 12, 12, 0.05),
                                     testing::Tolerance(1e-3));
  const LocatedVertices l = in->Located(true);
  ASSERT_EQ(l.deformed.size(), in->mesh.positions.size());
  EXPECT_EQ(l.outside, 0u);
  for (size_t k = 0; k < in->mesh.positions.size(); ++k) {
    const VertexId v(k);
    ASSERT_TRUE(l.on_sheet[v]);
    int hint = -1;
    EXPECT_LT((l.deformed[v] - in->map->Position(in->placed[k], OutsideMode::kClamp, &hint)).norm(),
              1e-12);
    // The analytic wrap: every point at radius 1 + h.
    EXPECT_NEAR(l.deformed[v].head<2>().norm(), 1.0 + in->placed[k].z(), 1e-12);
    SheetLocation at;
    ASSERT_TRUE(in->map->locator().Locate(in->placed[k].head<2>(), &at));
    EXPECT_EQ(l.cell[v], in->map->locator().CellIndex(at));
  }
}

TEST(VertexLocation, DeferredPositionsComeOutTheSame) {
  auto in = testing::MakeStageInputs(testing::Flattened(testing::BumpOnAPlane(0.3), 12),
                                     testing::FlatGrid(-1, -1, 2, 2, 9, 7, 0.1),
                                     testing::Tolerance(1e-3));
  const LocatedVertices now = in->Located(true);
  LocatedVertices later = in->Located(false);
  EXPECT_TRUE(later.deformed.empty());
  EXPECT_EQ(later.uv.size(), in->mesh.positions.size());
  CompleteDeformed(*in->ctx, &later);
  ASSERT_EQ(later.deformed.size(), now.deformed.size());
  for (size_t k = 0; k < now.deformed.size(); ++k) {
    EXPECT_EQ(later.deformed[VertexId(k)], now.deformed[VertexId(k)]) << k;
  }
}

TEST(VertexLocation, OffTheSheetIsAnErrorThatCountsThemOnlyWhenRefused) {
  PlacementOptions o;
  o.center_mode = CenterMode::kSheetUnits;  // at (u, v) = (0, 0), the sheet's corner:
  o.center = Vec2(0.0, 0.0);                // about three quarters of the grid off it
  for (OutsideMode mode : {OutsideMode::kError, OutsideMode::kClamp}) {
    o.outside = mode;
    auto in = testing::MakeStageInputs(testing::Cylinder(1.0),
                                       testing::FlatGrid(-0.5, -0.5, 1, 1, 4, 4, 0),
                                       testing::Tolerance(1e-3), o);
    auto l = LocateVertices(*in->ctx, true);
    if (mode == OutsideMode::kError) {
      ASSERT_FALSE(l.ok());
      EXPECT_EQ(l.status().code(), ErrorCode::kOutsideSheet);
    } else {
      ASSERT_TRUE(l.ok());
      EXPECT_GT(l->outside, 0u);
      EXPECT_LT(l->outside, in->mesh.positions.size());
      size_t off = 0;
      for (char c : l->on_sheet) off += c ? 0 : 1;
      EXPECT_EQ(off, l->outside);
      for (size_t k = 0; k < in->mesh.positions.size(); ++k) {
        if (!l->on_sheet[VertexId(k)]) {
          EXPECT_EQ(l->cell[VertexId(k)], -1);
        }
      }
    }
  }
}

}  // namespace
}  // namespace surfdeform::subdivision
