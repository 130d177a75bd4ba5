// Surfaces closed in u (closed-form sheets): a model across the
// seam of a full cylinder or cone, mapped through the sheet continued past
// it (engine/seam_extension.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "engine/animation/animation.hpp"
#include "engine/deform/deform.hpp"
#include "engine/flatten/seam_extension.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/sheet/sheet_marks.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 2.0, kHeight = 3.0;
constexpr double kTurn = 2.0 * kPi * kRadius;  // the full cylinder's circumference

SubdivisionOptions Off() {
  SubdivisionOptions o;
  o.mode = SubdivisionMode::kOff;
  return o;
}

Result<DeformResult> Deform(const testing::Target& t, const Mesh& m, const PlacementOptions& o,
                            const SubdivisionOptions& sub = Off()) {
  return Deform(SheetMap(*t.surface, t.sheet), Mesh(m), {.placement = o, .subdivision = sub});
}

double Radial(const Vec3& p) { return std::hypot(p.x(), p.y()); }

TEST(ClosedSurface, OnlyAWholeTurnUnrolledInClosedFormIsPeriodic) {
  const testing::Target full = testing::Flattened(CylinderSpec{kRadius, kHeight, 360.0, {}}, 17);
  const testing::Target half = testing::Flattened(CylinderSpec{kRadius, kHeight, 180.0, {}}, 17);
  EXPECT_TRUE(PeriodicInU(*full.surface, full.sheet));
  EXPECT_FALSE(PeriodicInU(*half.surface, half.sheet));
  EXPECT_TRUE(SheetMap(*full.surface, full.sheet).periodic_u());
  EXPECT_FALSE(SheetMap(*half.surface, half.sheet).periodic_u());
  // The strip continues by the period (2 pi R, 0): the copies of a column
  // one period apart.
  const auto x = ExtendAcrossSeam(*full.surface, full.sheet);
  ASSERT_NE(x, nullptr);
  EXPECT_EQ(x->period_columns, 16);
  for (int j = 0; j < x->sheet.nv; ++j) {
    const Vec2 a = x->sheet.flat[static_cast<size_t>(1 + x->sheet.nu * j)];
    const Vec2 b = x->sheet.flat[static_cast<size_t>(17 + x->sheet.nu * j)];
    EXPECT_LT((b - a - Vec2(kTurn, 0.0)).norm(), 1e-12 * kTurn) << j;
  }
  // A band across the seam of the half cylinder is still off its sheet.
  const Mesh band = testing::FlatGrid(-1.0, -0.2, 2.0, 0.4, 8, 2, 0.0);
  auto r = Deform(half, band, testing::KeepCoordinates(band, Vec2(0.0, kHeight / 2)));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kOutsideSheet);
}

TEST(ClosedSurface, ThePeriodIsATranslationForACylinderAndARotationForACone) {
  const testing::Target cylinder =
      testing::Flattened(CylinderSpec{kRadius, kHeight, 360.0, {}}, 17);
  const std::optional<SheetPeriod> strip = PeriodOf(*cylinder.surface, cylinder.sheet);
  ASSERT_TRUE(strip.has_value());
  EXPECT_NEAR(strip->angle, 0.0, 1e-12);
  EXPECT_LT((strip->translation - Vec2(kTurn, 0.0)).norm(), 1e-12 * kTurn);
  // A cone of radii 2 and 1 over height 2: slant sqrt(5), sector angle
  // 2 pi (2 - 1) / sqrt(5), about the apex (the motion's fixed point), which
  // lies 2 sqrt(5) from the bottom edge along the seam.
  const testing::Target cone = testing::Flattened(ConeSpec{2.0, 1.0, 2.0, 360.0, {}}, 17);
  const std::optional<SheetPeriod> sector = PeriodOf(*cone.surface, cone.sheet);
  ASSERT_TRUE(sector.has_value());
  EXPECT_NEAR(std::abs(sector->angle), 2.0 * kPi / std::sqrt(5.0), 1e-12);
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(sector->angle).toRotationMatrix();
  const Vec2 apex = (Eigen::Matrix2d::Identity() - r).inverse() * sector->translation;
  const Vec2 bottom = cone.sheet.flat[0];  // sample (0, 0), on the seam
  EXPECT_NEAR((apex - bottom).norm(), 2.0 * std::sqrt(5.0), 1e-9);
  EXPECT_FALSE(PeriodOf(*testing::Flattened(CylinderSpec{kRadius, kHeight, 359.0, {}}, 17).surface,
                        cylinder.sheet)
                   .has_value());
}

TEST(ClosedSurface, ABandOneCircumferenceLongCentredOnTheSeamCloses) {
  const testing::Target t = testing::Flattened(CylinderSpec{kRadius, kHeight, 360.0, {}}, 17);
  const int n = 96;  // cells along the band
  const Mesh band = testing::FlatGrid(-kTurn / 2, -0.25, kTurn, 0.5, n, 2, 0.0);
  auto r = Deform(t, band, testing::KeepCoordinates(band, Vec2(0.0, kHeight / 2)));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->stats.outside, 0u);
  EXPECT_NEAR(r->stats.turns, 1.0, 1e-9);
  const std::vector<Vec3>& p = r->mesh.positions;
  for (size_t k = 0; k < p.size(); ++k) {
    EXPECT_NEAR(Radial(p[k]), kRadius, 1e-9) << k;
    EXPECT_NEAR(p[k].z(), band.positions[k].y() + kHeight / 2, 1e-9) << k;
  }
  for (int row = 0; row <= 2; ++row) {  // the two ends of each row meet
    const size_t first = static_cast<size_t>(row) * (n + 1), last = first + n;
    EXPECT_LT((p[first] - p[last]).norm(), 1e-9) << "row " << row;
  }
}

TEST(ClosedSurface, AModelAcrossTheSeamIsTheModelHalfATurnAwayTurned) {
  const testing::Target t = testing::Flattened(CylinderSpec{kRadius, kHeight, 360.0, {}}, 33);
  const Mesh plate = testing::FlatGrid(-1.0, -0.6, 2.0, 1.2, 6, 4, 0.15);  // normals, tangents
  SubdivisionOptions fine;
  fine.tolerance = 0.002;
  for (const SubdivisionOptions& sub : {Off(), fine}) {
    auto across = Deform(t, plate, testing::KeepCoordinates(plate, Vec2(0.0, 1.4)), sub);
    auto away = Deform(t, plate, testing::KeepCoordinates(plate, Vec2(kTurn / 2, 1.4)), sub);
    ASSERT_TRUE(across.ok()) << across.status().ToString();
    ASSERT_TRUE(away.ok()) << away.status().ToString();
    const Mesh &a = across->mesh, &b = away->mesh;
    ASSERT_EQ(a.positions.size(), b.positions.size());
    if (sub.mode != SubdivisionMode::kOff) {
      EXPECT_GT(a.positions.size(), plate.positions.size()) << "refined across the seam";
    }
    // Half a turn about the axis: (x, y, z) -> (-x, -y, z).
    const Eigen::Matrix3d turn = Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal();
    double worst = 0.0;
    for (size_t k = 0; k < a.positions.size(); ++k) {
      worst = std::max(worst, (a.positions[k] - turn * b.positions[k]).norm());
      worst = std::max(worst, (a.normals[k] - turn * b.normals[k]).norm());
    }
    EXPECT_LT(worst, 1e-9) << (sub.mode == SubdivisionMode::kOff ? "off" : "refined");
  }
}

TEST(ClosedSurface, FitCrossesTheSeamButGoesRoundOnlyOnce) {
  const testing::Target t = testing::Flattened(CylinderSpec{kRadius, kHeight, 360.0, {}}, 17);
  // A long, low band: the height leaves room for 100x, the circumference
  // for about 0.42x.
  const Mesh band = testing::FlatGrid(-15.0, -0.01, 30.0, 0.02, 60, 1, 0.0);
  PlacementOptions o;
  o.center_mode = CenterMode::kSheetUnits;
  o.center = Vec2(0.0, kHeight / 2);  // on the seam
  o.fit = true;
  auto r = Deform(t, band, o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->stats.outside, 0u);
  EXPECT_LE(r->stats.turns, 1.0);
  EXPECT_GT(r->stats.turns, 0.999);  // to the bisection's 1e-5
  EXPECT_NEAR(r->stats.scale, kTurn / 30.0, 1e-4);
}

TEST(ClosedSurface, AModelLongerThanTheCircumferenceGoesRoundOverItself) {
  const testing::Target t = testing::Flattened(CylinderSpec{kRadius, kHeight, 360.0, {}}, 17);
  const Mesh band = testing::FlatGrid(-0.6 * kTurn, -0.2, 1.2 * kTurn, 0.4, 48, 2, 0.0);
  auto r = Deform(t, band, testing::KeepCoordinates(band, Vec2(kTurn / 2, kHeight / 2)));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_NEAR(r->stats.turns, 1.2, 1e-9);
  for (const Vec3& p : r->mesh.positions) EXPECT_NEAR(Radial(p), kRadius, 1e-9);
}

TEST(ClosedSurface, AConeBandAcrossTheSeamIsIsometricAndContinuous) {
  // A full cone, radius 2 at the bottom and 1 at the top: its sheet is an
  // annular sector of half a turn, continued past the seam by a rotation
  // about the apex.
  const ConeSpec cone{2.0, 1.0, 2.0, 360.0, {}};
  const testing::Target t = testing::Flattened(cone, 17);
  const SheetMap map(*t.surface, t.sheet);
  ASSERT_TRUE(map.periodic_u());
  const Vec2 seam = map.SheetPoint(map.MapParameters(Vec2(0.0, 0.5)));
  const Mesh band = testing::FlatGrid(-1.5, -0.2, 3.0, 0.4, 30, 4, 0.0);
  PlacementOptions o = testing::KeepCoordinates(band, seam);
  auto r = Deform(SheetMap(*t.surface, t.sheet), Mesh(band),
                  {.placement = o, .subdivision = Off(), .distortion = true});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->stats.outside, 0u);
  // On the cone (radius linear in height), and isometric: the map's
  // singular values are 1 everywhere, on both sides of the seam.
  for (const Vec3& p : r->mesh.positions) {
    EXPECT_NEAR(Radial(p), 2.0 - 0.5 * p.z(), 1e-9);
  }
  EXPECT_LT(r->stats.distortion.max, 1e-6);
}

TEST(ClosedSurface, RigidGlyphsAllRoundTheSeamKeepTheirShape) {
  // Twelve boxes, one every twelfth of a turn, the row centred on the seam:
  // each moves as a rigid body, so its pairwise distances stay.
  const testing::Target t = testing::Flattened(CylinderSpec{kRadius, kHeight, 360.0, {}}, 17);
  const Mesh glyphs = testing::GlyphRow(12, kTurn);
  PlacementOptions o = testing::KeepCoordinates(glyphs, Vec2(0.0, kHeight / 2));
  o.rigid = RigidMode::kComponents;
  auto r = Deform(t, glyphs, o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->stats.rigid.parts, 12);
  EXPECT_LT(testing::WorstGlyphStretch(glyphs, r->mesh), 1e-9);
  // The glyphs either side of the seam stand on it as the others do: each
  // box's base centre is on the cylinder.
  for (size_t g = 0; g < 12; ++g) {
    Vec3 base = Vec3::Zero();
    for (size_t k = 8 * g; k < 8 * g + 4; ++k) base += r->mesh.positions[k] / 4;  // z = 0 corners
    EXPECT_NEAR(Radial(base), kRadius, 1e-3) << g;
  }
}

TEST(ClosedSurface, AnAnimationCarriesTheModelAcrossTheSeamOnEveryFrame) {
  AnimationSpec spec;
  spec.keyframes = {{0.0, CylinderSpec{kRadius, kHeight, 360.0, {}}},
                    {1.0, CylinderSpec{1.5 * kRadius, kHeight, 360.0, {}}}};
  spec.frames = 4;
  auto sheets = FlattenAnimation(spec, {17, 9}, {});
  ASSERT_TRUE(sheets.ok()) << sheets.status().ToString();
  std::vector<SheetMap> maps;
  std::vector<const SheetMap*> pointers;
  for (size_t k = 0; k < sheets->sheets.size(); ++k) {
    maps.emplace_back(*sheets->surfaces[k], sheets->sheets[k]);
  }
  for (const SheetMap& m : maps) pointers.push_back(&m);
  const Mesh band = testing::FlatGrid(-2.0, -0.2, 4.0, 0.4, 16, 2, 0.0);
  const PlacementOptions o = testing::KeepCoordinates(band, Vec2(0.0, kHeight / 2));
  auto model = PrepareModel(pointers, Mesh(band), {.placement = o, .subdivision = Off()});
  ASSERT_TRUE(model.ok()) << model.status().ToString();
  for (int k = 0; k < spec.frames; ++k) {
    const double radius = std::get<CylinderSpec>(SurfaceAtFrame(spec, k)).radius;
    auto frame = DeformPrepared(maps[k], *model, k, {.placement = o});
    ASSERT_TRUE(frame.ok()) << "frame " << k << ": " << frame.status().ToString();
    for (const Vec3& p : frame->mesh.positions) EXPECT_NEAR(Radial(p), radius, 1e-9) << k;
  }
}

TEST(ClosedSurface, TheMapAnswersModuloThePeriod) {
  const testing::Target t = testing::Flattened(CylinderSpec{kRadius, kHeight, 360.0, {}}, 17);
  const SheetMap map(*t.surface, t.sheet);
  for (const Vec2& p : {Vec2(0.3, 1.0), Vec2(kTurn - 0.2, 2.5), Vec2(kTurn / 2, 0.1)}) {
    const SheetMark on = MarkAt(map, p);
    for (const Vec2& q : {Vec2(p + Vec2(kTurn / 2, 0.0)), Vec2(p - Vec2(kTurn / 2, 0.0))}) {
      const SheetMark other = MarkAt(map, q);
      EXPECT_TRUE(other.on_sheet);
      EXPECT_LT((other.point - Eigen::Vector3d(-1, -1, 1).asDiagonal() * on.point).norm(), 1e-12);
    }
    const SheetMark round = MarkAt(map, p + Vec2(kTurn, 0.0));
    if (p.x() + kTurn <= 1.5 * kTurn) {
      EXPECT_LT((round.point - on.point).norm(), 1e-12);
      EXPECT_NEAR(round.uv.x(), on.uv.x(), 1e-12);  // u in [0, 1): modulo the period
    }
    EXPECT_GE(on.uv.x(), 0.0);
    EXPECT_LT(on.uv.x(), 1.0);
    // The nearest point of a surface point is on the given sheet.
    const SheetMark back = MarkNearest(map, on.point);
    EXPECT_LT((back.sheet - p).norm(), 1e-9) << p.transpose();
  }
}

}  // namespace
}  // namespace surfdeform
