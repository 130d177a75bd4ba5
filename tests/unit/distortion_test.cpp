// The distortion map of a deformation: analytic cases (a cylinder unrolls
// isometrically; off the mid surface lengths across it scale as the radius),
// finite differences of the map on a Bezier patch, and its statistics.
#include "engine/deform/distortion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/deform/deform.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

using testing::Flattened;
using testing::KeepCoordinates;
using testing::Target;
using Mat32 = Eigen::Matrix<double, 3, 2>;

DeformResult WithDistortion(const Target& t, Mesh m, const PlacementOptions& o,
                            SubdivisionMode mode = SubdivisionMode::kOff) {
  SubdivisionOptions s;
  s.mode = mode;
  auto r = Deform(SheetMap(*t.surface, t.sheet), std::move(m),
                  {.placement = o, .subdivision = s, .distortion = true});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? std::move(r).value() : DeformResult{};
}

TEST(Distortion, SingularValuesOfKnownMatrices) {
  Mat32 j = Mat32::Zero();
  j(0, 0) = 2.0;
  j(1, 1) = 3.0;
  EXPECT_NEAR(SingularValues(j).x(), 3.0, 1e-15);
  EXPECT_NEAR(SingularValues(j).y(), 2.0, 1e-15);
  // Rotations on either side change nothing.
  const Eigen::Matrix3d r3 = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix2d r2 = Eigen::Rotation2Dd(1.1).toRotationMatrix();
  const Vec2 s = SingularValues(r3 * j * r2);
  EXPECT_NEAR(s.x(), 3.0, 1e-14);
  EXPECT_NEAR(s.y(), 2.0, 1e-14);
  // Rank one: the second is 0; a shear's are those of its Gram matrix.
  j.col(1) = 2.0 * j.col(0);
  EXPECT_NEAR(SingularValues(j).y(), 0.0, 1e-15);
  Mat32 shear = Mat32::Zero();
  shear << 1, 1, 0, 1, 0, 0;  // [[1, 1], [0, 1]]: s = (1 +- sqrt 5) / 2 in absolute value
  EXPECT_NEAR(SingularValues(shear).x(), (1 + std::sqrt(5.0)) / 2, 1e-15);
  EXPECT_NEAR(SingularValues(shear).y(), (std::sqrt(5.0) - 1) / 2, 1e-15);
}

TEST(Distortion, ACylindersMidSurfaceIsAnIsometryAndOffsetsScaleWithTheRadius) {
  const double radius = 2.0, height = 3.0;
  const Target t = Flattened(CylinderSpec{radius, height, 180.0, {}}, 16);
  const Vec2 at(std::numbers::pi * radius / 2, height / 2);
  // On the mid surface (h = 0), with and without subdivision (which adds vertices).
  const Mesh flat = testing::FlatGrid(-2.0, -1.0, 4.0, 2.0, 20, 10, 0.0);
  for (SubdivisionMode mode : {SubdivisionMode::kOff, SubdivisionMode::kAdaptive}) {
    const DeformResult r = WithDistortion(t, flat, KeepCoordinates(flat, at), mode);
    ASSERT_EQ(r.mesh.distortion.size(), r.mesh.positions.size());
    for (const Vec2& d : r.mesh.distortion)
      EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-9) << d.transpose();
    EXPECT_TRUE(r.stats.distortion.computed);
    EXPECT_LT(r.stats.distortion.max, 1e-9);
  }
  // A plate 0.4 thick: at height h lengths across the axis scale by (R + h) / R,
  // along it not at all. r is each output vertex's distance from the axis (z).
  const Mesh plate = testing::ThinPlate(4.0, 2.0, 0.4);
  const DeformResult r = WithDistortion(t, plate, KeepCoordinates(plate, at));
  double worst = 0.0;
  for (size_t k = 0; k < plate.positions.size(); ++k) {
    const double across = r.mesh.positions[k].head<2>().norm() / radius;
    const Vec2 want = across >= 1.0 ? Vec2(across - 1.0, 0.0) : Vec2(0.0, across - 1.0);
    EXPECT_LT((r.mesh.distortion[k] - want).norm(), 1e-9) << k;
    worst = std::max(worst, std::abs(across - 1.0));
  }
  EXPECT_NEAR(worst, 0.2 / radius, 1e-9);  // the faces at h = +-0.2
  EXPECT_NEAR(r.stats.distortion.max, 0.2 / radius, 1e-9);
  EXPECT_NEAR(r.stats.distortion.p95, 0.2 / radius, 1e-9);
}

TEST(Distortion, MatchesFiniteDifferencesOfTheMapOnABezierPatch) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  const SheetMap map(*t.surface, t.sheet);
  const Vec2 centre = map.locator().bounds().center();
  Mesh grid = testing::FlatGrid(-3.0, -3.0, 6.0, 6.0, 24, 24, 0.0);
  for (size_t k = 0; k < grid.positions.size(); ++k) grid.positions[k].z() = 0.3 * std::sin(k);
  const DeformResult r = WithDistortion(t, grid, KeepCoordinates(grid, centre));
  ASSERT_EQ(r.mesh.distortion.size(), grid.positions.size());
  const double step = 1e-6;
  int tested = 0;
  double largest = 0.0;
  for (size_t k = 0; k < grid.positions.size(); ++k) {
    const Vec3 abh = grid.positions[k] + Vec3(centre.x(), centre.y(), 0.0);
    // Central differences only inside one cell: the bilinear map has kinks at cell sides.
    SheetLocation loc;
    ASSERT_TRUE(map.locator().Locate(abh.head<2>(), &loc));
    if (std::min({loc.s, loc.t, 1 - loc.s, 1 - loc.t}) < 1e-3) continue;
    auto f = [&](double da, double db) {
      return map.Position(abh + Vec3(da, db, 0.0), OutsideMode::kError, nullptr);
    };
    Mat32 j;
    j.col(0) = (f(step, 0) - f(-step, 0)) / (2 * step);
    j.col(1) = (f(0, step) - f(0, -step)) / (2 * step);
    const Vec2 want = SingularValues(j) - Vec2::Ones();
    EXPECT_LT((r.mesh.distortion[k] - want).norm(), 1e-6) << k;
    largest = std::max(largest, want.cwiseAbs().maxCoeff());
    ++tested;
  }
  EXPECT_GT(tested, 400);    // of 576
  EXPECT_GT(largest, 1e-2);  // the patch bends: the comparison is not of zeros
}

TEST(Distortion, StatsAreTheMaxTheNearestRankP95AndTheAreaWeightedMean) {
  Mesh m = testing::FlatGrid(0.0, 0.0, 2.0, 1.0, 2, 1, 0.0);  // two unit squares
  ASSERT_EQ(m.positions.size(), 6u);
  // Vertices 0..5 row by row; distortions chosen so the area weights matter.
  m.distortion = {Vec2(0.1, 0), Vec2(0, -0.2), Vec2(0.3, 0.0),
                  Vec2(0, 0),   Vec2(0, 0),    Vec2(0.05, -0.4)};
  const DistortionStats st = SummarizeDistortion(m);
  ASSERT_TRUE(st.computed);
  EXPECT_DOUBLE_EQ(st.max, 0.4);
  EXPECT_DOUBLE_EQ(st.p95, 0.4);  // ceil(0.95 * 6) = 6th of 6
  std::vector<double> weight(6, 0.0);
  double total = 0.0;
  for (const auto& tri : m.triangles) {
    const double third = (m.positions[tri[1]] - m.positions[tri[0]])
                             .cross(m.positions[tri[2]] - m.positions[tri[0]])
                             .norm() /
                         6.0;
    for (uint32_t v : tri) weight[v] += third;
    total += 3 * third;
  }
  EXPECT_NEAR(total, 2.0, 1e-12);
  const double d[6] = {0.1, 0.2, 0.3, 0.0, 0.0, 0.4};
  double mean = 0.0;
  for (int k = 0; k < 6; ++k) mean += weight[k] * d[k] / total;
  EXPECT_NEAR(st.mean, mean, 1e-15);
  EXPECT_FALSE(SummarizeDistortion(testing::FlatGrid(0, 0, 1, 1, 1, 1, 0)).computed);
}

TEST(Distortion, OnlyWhenAskedFor) {
  const Target t = Flattened(CylinderSpec{2.0, 3.0, 180.0, {}}, 8);
  const Mesh flat = testing::FlatGrid(-1.0, -1.0, 2.0, 2.0, 4, 4, 0.0);
  auto r = Deform(SheetMap(*t.surface, t.sheet), flat,
                  {.placement = KeepCoordinates(flat, Vec2(3.0, 1.5))});
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->mesh.distortion.empty());
  EXPECT_FALSE(r->stats.distortion.computed);
}

}  // namespace
}  // namespace surfdeform
