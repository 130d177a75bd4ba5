// The sheet-to-surface map sampled on a lattice (engine/sheet_field.hpp):
// a plane's field is the plane itself, a cylinder's lies on the cylinder with
// radial normals, lattice points on the sheet carry exactly SheetMap's
// values, points off a cone's curved sheet are flagged and continue the map
// smoothly, and the result does not depend on the threads.
#include "engine/sheet/sheet_field.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

using testing::Flattened;

// A bilinear Bezier square [0, 2] x [0, 1] in z = 0.
BezierSpec FlatRectangle() {
  BezierSpec b;
  b.degree_u = b.degree_v = 1;
  b.control_points = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(2, 1, 0)};
  return b;
}

TEST(SheetField, APlaneMapsToItself) {
  const auto t = Flattened(FlatRectangle(), 8);
  ASSERT_FALSE(t.sheet.flat.empty());
  const SheetMap map(*t.surface, t.sheet);
  auto f = SampleSheetField(map, 17, 1);
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  EXPECT_EQ(f->n, 17);
  EXPECT_NEAR((f->hi - f->lo).x(), 2.0, 1e-9);  // the canonical sheet: u along +X
  EXPECT_NEAR((f->hi - f->lo).y(), 1.0, 1e-9);
  ASSERT_EQ(f->positions.size(), 17u * 17u);
  for (int j = 0; j < 17; ++j) {
    for (int i = 0; i < 17; ++i) {
      const size_t k = i + 17 * j;
      const Vec2 ab = f->lo + Vec2(i * 2.0 / 16, j * 1.0 / 16);
      // The sheet is the rectangle moved to the origin: P = (a, b, 0) + offset.
      EXPECT_NEAR((f->positions[k] - Vec3(ab.x() - f->lo.x(), ab.y() - f->lo.y(), 0)).norm(), 0.0,
                  1e-9)
          << i << ", " << j;
      EXPECT_NEAR(std::abs(f->normals[k].z()), 1.0, 1e-12);
      EXPECT_EQ(f->on_sheet[k], 1) << i << ", " << j;  // the box is the sheet
    }
  }
}

TEST(SheetField, ACylindersFieldLiesOnItWithRadialNormalsAndMatchesTheMap) {
  CylinderSpec c;
  c.radius = 2.0;
  c.height = 3.0;
  c.angle_deg = 180.0;
  const auto t = Flattened(c, 16);
  const SheetMap map(*t.surface, t.sheet);
  auto f = SampleSheetField(map, 33, 1);
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  int on = 0;
  const Vec2 step = (f->hi - f->lo) / 32.0;
  for (int j = 0; j < 33; ++j) {
    for (int i = 0; i < 33; ++i) {
      const size_t k = i + 33 * j;
      const Vec3& p = f->positions[k];
      EXPECT_NEAR(std::hypot(p.x(), p.y()), 2.0, 1e-9) << i << ", " << j;
      const Vec3 radial = Vec3(p.x(), p.y(), 0).normalized();
      EXPECT_NEAR(std::abs(f->normals[k].dot(radial)), 1.0, 1e-9);
      if (f->on_sheet[k] == 0) continue;
      ++on;
      const Vec2 ab(i + 1 == 33 ? f->hi.x() : f->lo.x() + i * step.x(),
                    j + 1 == 33 ? f->hi.y() : f->lo.y() + j * step.y());
      Vec3 point, normal;
      map.SurfaceAndNormal(ab, OutsideMode::kError, nullptr, &point, &normal);
      EXPECT_EQ(p, point);  // the same bits as the map's
      EXPECT_EQ(f->normals[k], normal);
    }
  }
  EXPECT_EQ(on, 33 * 33);  // an unrolled cylinder is a rectangle
}

TEST(SheetField, PointsOffACurvedSheetAreFlaggedAndContinueTheMapSmoothly) {
  ConeSpec c;  // unrolls to an annular sector: its bounding box has corners off it
  c.radius_bottom = 2.0;
  c.radius_top = 1.0;
  c.height = 1.0;
  c.angle_deg = 180.0;
  const auto t = Flattened(c, 16);
  const SheetMap map(*t.surface, t.sheet);
  const int n = 41;
  auto f = SampleSheetField(map, n, 1);
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  int off = 0;
  double worst_jump = 0.0;  // between neighbours, relative to the lattice step
  const double step = ((f->hi - f->lo) / (n - 1)).norm();
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const size_t k = i + n * j;
      off += f->on_sheet[k] == 0;
      ASSERT_TRUE(f->positions[k].allFinite() && f->normals[k].allFinite());
      EXPECT_NEAR(f->normals[k].norm(), 1.0, 1e-12);
      // Every point, on the sheet or continued off it, is the surface at
      // its params.
      const Vec2& uv = f->params[k];
      EXPECT_EQ(f->positions[k], t.surface->Evaluate(uv.x(), uv.y(), 1).p) << i << ", " << j;
      if (i + 1 < n) {
        worst_jump = std::max(worst_jump, (f->positions[k + 1] - f->positions[k]).norm() / step);
      }
      if (j + 1 < n) {
        worst_jump = std::max(worst_jump, (f->positions[k + n] - f->positions[k]).norm() / step);
      }
    }
  }
  EXPECT_GT(off, n);              // the sector's corners
  EXPECT_LT(off, n * n * 3 / 4);  // a 127-degree sector of a ring fills about half its box
  // A continuous continuation: neighbours at most a few steps apart on the
  // surface (a jump across the border would be a fraction of the sheet).
  EXPECT_LT(worst_jump, 4.0);
}

TEST(SheetField, IsTheSameOnAnyThreadsAndRefusesTooSmallALattice) {
  const auto t = Flattened(testing::BumpOnAPlane(0.3), 24);
  const SheetMap map(*t.surface, t.sheet);
  auto one = SampleSheetField(map, 50, 1);
  auto two = SampleSheetField(map, 50, 2);
  ASSERT_TRUE(one.ok() && two.ok());
  EXPECT_EQ(one->positions, two->positions);
  EXPECT_EQ(one->normals, two->normals);
  EXPECT_EQ(one->on_sheet, two->on_sheet);
  auto tiny = SampleSheetField(map, 1, 1);
  ASSERT_FALSE(tiny.ok());
  EXPECT_EQ(tiny.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(tiny.status().field(), "n");
}

}  // namespace
}  // namespace surfdeform
