// Periodic flattening (phase two): a surface closed in u that is
// not unrolled in closed form is flattened into a strip with a period T,
// the pairs across the seam counted in the stress like any others.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "engine/animation/animation.hpp"
#include "engine/deform/deform.hpp"
#include "engine/flatten/flatten.hpp"
#include "engine/flatten/seam_extension.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/sheet/sheet_marks.hpp"
#include "engine/surface/surface_spec.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

constexpr double kPi = std::numbers::pi;

struct Flat {
  std::unique_ptr<Surface> surface;
  FlatSheet sheet;
};

Flat FlattenSpec(const SurfaceSpec& spec, int nu, int nv, FlattenOptions o = {}) {
  Flat f;
  auto s = MakeSurface(spec);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  if (!s.ok()) return f;
  f.surface = std::move(*s);
  auto sheet = FlattenSurface(*f.surface, {nu, nv}, o);
  EXPECT_TRUE(sheet.ok()) << sheet.status().ToString();
  if (sheet.ok()) f.sheet = std::move(*sheet);
  return f;
}

SubdivisionOptions Off() {
  SubdivisionOptions o;
  o.mode = SubdivisionMode::kOff;
  return o;
}

// The best rigid motion of the plane (no reflection) from a to b, applied
// to a: the largest distance left.
double RigidResidual(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  Vec2 ca = Vec2::Zero(), cb = Vec2::Zero();
  for (size_t k = 0; k < a.size(); ++k) {
    ca += a[k] / a.size();
    cb += b[k] / b.size();
  }
  double dot = 0.0, cross = 0.0;
  for (size_t k = 0; k < a.size(); ++k) {
    dot += (a[k] - ca).dot(b[k] - cb);
    cross += Cross2(a[k] - ca, b[k] - cb);
  }
  const double angle = std::atan2(cross, dot);
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(angle).toRotationMatrix();
  double worst = 0.0;
  for (size_t k = 0; k < a.size(); ++k) {
    worst = std::max(worst, (r * (a[k] - ca) + cb - b[k]).norm());
  }
  return worst;
}

// 24 rigid glyphs in a row one period_u long, centred on surface point `uv`
// of a periodic sheet: each keeps its shape (to 1e-9) and none is off the
// sheet. Returns the deformed glyphs.
Mesh RigidGlyphsRound(const Flat& f, const Vec2& uv) {
  const SheetMap map(*f.surface, f.sheet);
  constexpr int kGlyphs = 24;
  const Mesh glyphs = testing::GlyphRow(kGlyphs, f.sheet.period_u.norm());
  PlacementOptions o = testing::KeepCoordinates(glyphs, map.SheetPoint(map.MapParameters(uv)));
  o.rigid = RigidMode::kComponents;
  auto r =
      Deform(SheetMap(*f.surface, f.sheet), Mesh(glyphs), {.placement = o, .subdivision = Off()});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  if (!r.ok()) return Mesh();
  EXPECT_EQ(r->stats.rigid.parts, kGlyphs);
  EXPECT_EQ(r->stats.outside, 0u);
  EXPECT_LT(testing::WorstGlyphStretch(glyphs, r->mesh), 1e-9);
  return std::move(r->mesh);
}

TEST(PeriodicFlatten, AWholeCylinderFlattenedByStressHasItsCircumferenceForPeriod) {
  const double radius = 2.0, turn = 2.0 * kPi * radius;
  FlattenOptions o;
  o.exact_developable = false;
  o.tolerance = 1e-14;
  const Flat f = FlattenSpec(CylinderSpec{radius, 3.0, 360.0, {}}, 33, 9, o);
  ASSERT_EQ(f.sheet.nu, 33);
  EXPECT_EQ(f.sheet.method, "majorization");
  EXPECT_TRUE(PeriodicInU(*f.surface, f.sheet));
  // The distances are measured to ~1e-7 (a pair's arc from its chord and
  // tangents), and the stress reaches that: the strip is the development.
  EXPECT_LT(f.sheet.quality.stress, 1e-6);
  EXPECT_NEAR(f.sheet.period_u.norm(), turn, 1e-6 * turn);
  EXPECT_NEAR(f.sheet.period_u.y(), 0.0, 1e-6 * turn);  // along the seam's normal
  // Column nu - 1 is column 0 a period on.
  for (int j = 0; j < 9; ++j) {
    EXPECT_LT((f.sheet.flat[32 + 33 * j] - f.sheet.flat[33 * j] - f.sheet.period_u).norm(), 1e-12);
  }
  // Its period is the exact one's.
  const Flat exact = FlattenSpec(CylinderSpec{radius, 3.0, 360.0, {}}, 33, 9);
  EXPECT_NEAR(PeriodOf(*exact.surface, exact.sheet)->translation.x(), turn, 1e-12 * turn);
}

TEST(PeriodicFlatten, OnlySurfacesThatCloseAndGridsWithRoomAreFlattenedPeriodic) {
  FlattenOptions o;
  const auto belt = MakeSurface(SphereSpec{1.0, 0.0, 360.0, -40.0, 40.0, {}});
  const auto part = MakeSurface(SphereSpec{1.0, 0.0, 359.0, -40.0, 40.0, {}});
  ASSERT_TRUE(belt.ok() && part.ok());
  EXPECT_EQ(PeriodicColumns(**belt, 17, o), 16);
  EXPECT_EQ(PeriodicColumns(**part, 17, o), 0);
  EXPECT_EQ(PeriodicColumns(**belt, 7, o), 0);  // 6 columns: no room for range 3 each way
  EXPECT_EQ(PeriodicColumns(**belt, 8, o), 7);
  o.method = FlattenMethod::kPaper;
  EXPECT_EQ(PeriodicColumns(**belt, 17, o), 0);
  const Flat open = FlattenSpec(SphereSpec{1.0, 0.0, 360.0, -40.0, 40.0, {}}, 7, 5);
  EXPECT_TRUE(open.sheet.period_u.isZero());
  EXPECT_FALSE(PeriodicInU(*open.surface, open.sheet));
}

TEST(PeriodicFlatten, TheSheetDoesNotDependOnWhereTheSeamIs) {
  // The same sphere belt, its seam at longitude 0 and 5 columns on (37.5
  // degrees): the same samples, so the same sheet up to a rigid motion.
  FlattenOptions o;
  o.tolerance = 1e-13;
  const int p = 48, shift = 5;
  const Flat a = FlattenSpec(SphereSpec{1.0, 0.0, 360.0, -40.0, 40.0, {}}, p + 1, 13, o);
  const double lon = 360.0 * shift / p;
  const Flat b = FlattenSpec(SphereSpec{1.0, lon, lon + 360.0, -40.0, 40.0, {}}, p + 1, 13, o);
  std::vector<Vec2> pa, pb;
  for (int j = 0; j < 13; ++j) {
    for (int i = 0; i < p; ++i) {
      pa.push_back(a.sheet.flat[(i + shift) % p + (p + 1) * j] +
                   ((i + shift) / p) * a.sheet.period_u);
      pb.push_back(b.sheet.flat[i + (p + 1) * j]);
    }
  }
  EXPECT_LT(RigidResidual(pa, pb), 1e-6);
  EXPECT_NEAR(a.sheet.period_u.norm(), b.sheet.period_u.norm(), 1e-7);
  EXPECT_NEAR(a.sheet.quality.stress, b.sheet.quality.stress, 1e-7);
}

TEST(PeriodicFlatten, TheQualityCoversTheSeam) {
  // The stress counts the pairs across the seam: a belt's periodic sheet
  // keeps them, and measures them, where an open one cut there need not.
  const Flat f = FlattenSpec(SphereSpec{1.0, 0.0, 360.0, -40.0, 40.0, {}}, 33, 13);
  EXPECT_EQ(f.sheet.quality.folded_cells, 0);
  EXPECT_GT(f.sheet.quality.stress, 0.0);
  EXPECT_LT(f.sheet.quality.stress, 0.1);
  // The ring-1 edges across the seam (column 31 to column 32 = 0 + T) are
  // as long as those anywhere else in their row: the belt turns into itself.
  for (int j = 0; j < 13; ++j) {
    const double seam = (f.sheet.flat[32 + 33 * j] - f.sheet.flat[31 + 33 * j]).norm();
    const double middle = (f.sheet.flat[17 + 33 * j] - f.sheet.flat[16 + 33 * j]).norm();
    EXPECT_NEAR(seam, middle, 1e-6 * middle) << j;
  }
}

TEST(PeriodicFlatten, ABandAcrossASphereBeltsSeamLiesOnTheSphere) {
  FlattenOptions o;
  o.tolerance = 1e-12;
  const Flat f = FlattenSpec(SphereSpec{1.5, 0.0, 360.0, -40.0, 40.0, {}}, 49, 13, o);
  const SheetMap map(*f.surface, f.sheet);
  ASSERT_TRUE(map.periodic_u());
  const Vec2 seam = map.SheetPoint(map.MapParameters(Vec2(0.0, 0.5)));
  const Vec2 half = map.SheetPoint(map.MapParameters(Vec2(0.5, 0.5)));
  const Mesh band = testing::FlatGrid(-2.0, -0.3, 4.0, 0.6, 40, 4, 0.0);
  auto across = Deform(SheetMap(*f.surface, f.sheet), Mesh(band),
                       {.placement = testing::KeepCoordinates(band, seam),
                        .subdivision = Off(),
                        .distortion = true});
  auto away = Deform(SheetMap(*f.surface, f.sheet), Mesh(band),
                     {.placement = testing::KeepCoordinates(band, half),
                      .subdivision = Off(),
                      .distortion = true});
  ASSERT_TRUE(across.ok()) << across.status().ToString();
  ASSERT_TRUE(away.ok()) << away.status().ToString();
  EXPECT_EQ(across->stats.outside, 0u);
  for (const Vec3& p : across->mesh.positions) EXPECT_NEAR(p.norm(), 1.5, 1e-9);
  // Half a turn away, turned back, it is the same band, its distortion too:
  // the periodic sheet is the same on both sides of the seam.
  const Eigen::Matrix3d turn = Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal();
  double worst = 0.0, worst_distortion = 0.0;
  for (size_t k = 0; k < band.positions.size(); ++k) {
    worst = std::max(worst, (across->mesh.positions[k] - turn * away->mesh.positions[k]).norm());
    worst_distortion =
        std::max(worst_distortion, (across->mesh.distortion[k] - away->mesh.distortion[k]).norm());
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_distortion, 1e-5);
  // Refined: the faces across the seam are subdivided like any other, and
  // the points added lie on the sphere too.
  SubdivisionOptions fine;
  fine.tolerance = 0.002;
  auto refined = Deform(SheetMap(*f.surface, f.sheet), Mesh(band),
                        {.placement = testing::KeepCoordinates(band, seam), .subdivision = fine});
  ASSERT_TRUE(refined.ok()) << refined.status().ToString();
  EXPECT_GT(refined->mesh.positions.size(), band.positions.size());
  for (const Vec3& p : refined->mesh.positions) EXPECT_NEAR(p.norm(), 1.5, 1e-9);
  // The map answers modulo the period: a sheet point and the point a
  // period on are one surface point, with u in [0, 1).
  for (const Vec2& p : {Vec2(seam + Vec2(0.1, 0.2)), Vec2(half - Vec2(0.3, 0.1))}) {
    const SheetMark on = MarkAt(map, p), round = MarkAt(map, p + f.sheet.period_u);
    EXPECT_TRUE(on.on_sheet && round.on_sheet);
    EXPECT_LT((on.point - round.point).norm(), 1e-9);
    EXPECT_NEAR(on.uv.x(), round.uv.x(), 1e-9);
    EXPECT_GE(on.uv.x(), 0.0);
    EXPECT_LT(on.uv.x(), 1.0);
  }
}

TEST(PeriodicFlatten, RigidGlyphsAllRoundATorusKeepTheirShape) {
  // 24 boxes all round a torus ring (its whole turn about the axis, the
  // outer half of the tube), the row centred on the seam.
  const Flat f = FlattenSpec(TorusSpec{3.0, 1.0, 0.0, 360.0, -70.0, 70.0, {}}, 73, 17);
  ASSERT_TRUE(SheetMap(*f.surface, f.sheet).periodic_u());
  const Mesh r = RigidGlyphsRound(f, Vec2(0.0, 0.5));
  // Each box stands on the outer equator, the seam's neighbours as well.
  for (size_t g = 0; g < 24; ++g) {
    Vec3 base = Vec3::Zero();
    for (size_t k = 8 * g; k < 8 * g + 4; ++k) base += r.positions[k] / 4;
    EXPECT_NEAR(std::hypot(base.x(), base.y()), 4.0, 0.02) << g;
  }
}

TEST(PeriodicFlatten, AnAnimationOfSphereBeltsCarriesTheBandAcrossTheSeam) {
  AnimationSpec spec;
  spec.keyframes = {{0.0, SphereSpec{1.0, 0.0, 360.0, -40.0, 40.0, {}}},
                    {1.0, SphereSpec{1.6, 0.0, 360.0, -40.0, 40.0, {}}}};
  spec.frames = 5;
  auto sheets = FlattenAnimation(spec, {33, 9}, {});
  ASSERT_TRUE(sheets.ok()) << sheets.status().ToString();
  std::vector<SheetMap> maps;
  std::vector<const SheetMap*> pointers;
  for (size_t k = 0; k < sheets->sheets.size(); ++k) {
    EXPECT_FALSE(sheets->sheets[k].period_u.isZero()) << k;
    maps.emplace_back(*sheets->surfaces[k], sheets->sheets[k]);
  }
  for (const SheetMap& m : maps) pointers.push_back(&m);
  const Mesh band = testing::FlatGrid(-1.5, -0.2, 3.0, 0.4, 24, 2, 0.0);
  PlacementOptions o = testing::KeepCoordinates(band, Vec2::Zero());
  o.center_mode = CenterMode::kFraction;
  o.center = Vec2(0.0, 0.5);  // on the seam, on every frame
  auto model = PrepareModel(pointers, Mesh(band), {.placement = o, .subdivision = Off()});
  ASSERT_TRUE(model.ok()) << model.status().ToString();
  for (int k = 0; k < spec.frames; ++k) {
    ASSERT_TRUE(maps[k].periodic_u()) << k;
    const double radius = std::get<SphereSpec>(SurfaceAtFrame(spec, k)).radius;
    auto frame = DeformPrepared(maps[k], *model, k, {.placement = o});
    ASSERT_TRUE(frame.ok()) << "frame " << k << ": " << frame.status().ToString();
    for (const Vec3& p : frame->mesh.positions) EXPECT_NEAR(p.norm(), radius, 1e-9) << k;
  }
}

TEST(PeriodicFlatten, ASplineDeclaredPeriodicMustClose) {
  // A whole NURBS cylinder's net closes (its first and last columns are
  // equal): accepted, and closed in u.
  BSplineSpec can = testing::NurbsCone(1.0, 1.0, 2.0, 360.0);
  can.periodic_u = true;
  auto closed = MakeSurface(can);
  ASSERT_TRUE(closed.ok()) << closed.status().ToString();
  EXPECT_TRUE((*closed)->ClosedInU());
  EXPECT_TRUE(ClosesInU(can));
  // Nine tenths of a turn does not: 422 saying by how much.
  BSplineSpec part = testing::NurbsCone(1.0, 1.0, 2.0, 324.0);
  part.periodic_u = true;
  auto open = MakeSurface(part);
  ASSERT_FALSE(open.ok());
  EXPECT_EQ(open.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(open.status().field(), "periodic_u");
  // The gap is the chord of the missing tenth: 2 sin(18 degrees).
  const std::string gap = std::to_string(2.0 * std::sin(kPi / 10)).substr(0, 5);
  EXPECT_NE(open.status().message().find("fails to meet by " + gap), std::string::npos)
      << open.status().message();
  // A grid whose last column is not its first, likewise.
  GridSpec grid = testing::GridCylinder(1.0, 2.0, 300.0, 11, 4);
  grid.periodic_u = true;
  auto g = MakeSurface(grid);
  ASSERT_FALSE(g.ok());
  EXPECT_EQ(g.status().field(), "periodic_u");
}

TEST(PeriodicFlatten, APeriodicBSplineWithUniformKnotsIsAccepted) {
  // A uniform cubic B-spline ring: 8 control points round a circle and the
  // first 3 again, unclamped uniform knots. It closes, C2.
  BSplineSpec s;
  s.degree_u = 3;
  s.degree_v = 1;
  s.count_u = 11;
  s.count_v = 2;
  for (int k = 0; k < 15; ++k) s.knots_u.push_back((k - 3) / 8.0);
  s.knots_v = {0, 0, 1, 1};
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 11; ++i) {
      const double a = 2.0 * kPi * (i % 8) / 8;
      s.control_points.emplace_back(std::cos(a), std::sin(a), 1.5 * j);
    }
  }
  auto clamped = MakeSurface(s);
  ASSERT_FALSE(clamped.ok());  // unclamped knots need periodic_u
  EXPECT_EQ(clamped.status().field(), "knots_u");
  s.periodic_u = true;
  auto ring = MakeSurface(s);
  ASSERT_TRUE(ring.ok()) << ring.status().ToString();
  const SurfacePoint a = (*ring)->Evaluate(0.0, 0.5, 2), b = (*ring)->Evaluate(1.0, 0.5, 2);
  EXPECT_LT((a.p - b.p).norm(), 1e-12);
  EXPECT_LT((a.su - b.su).norm(), 1e-12);
  EXPECT_LT((a.suu - b.suu).norm(), 1e-12);
  auto sheet = FlattenSurface(**ring, {33, 5});
  ASSERT_TRUE(sheet.ok()) << sheet.status().ToString();
  EXPECT_FALSE(sheet->period_u.isZero());
}

TEST(PeriodicFlatten, APeriodicGridIsInterpolatedRoundTheSeam) {
  // A cylinder of radius 2 sampled at 24 columns and the first again: the
  // periodic spline is C2 across the seam and near the cylinder, and its
  // sheet's period is the circumference to the interpolation's error.
  GridSpec grid = testing::GridCylinder(2.0, 3.0, 360.0, 25, 5);
  grid.periodic_u = true;
  auto surface = MakeSurface(grid);
  ASSERT_TRUE(surface.ok()) << surface.status().ToString();
  ASSERT_TRUE((*surface)->ClosedInU());
  const SurfacePoint a = (*surface)->Evaluate(0.0, 0.3, 2), b = (*surface)->Evaluate(1.0, 0.3, 2);
  EXPECT_LT((a.p - b.p).norm(), 1e-12);
  EXPECT_LT((a.su - b.su).norm(), 1e-9 * a.su.norm());
  EXPECT_LT((a.suu - b.suu).norm(), 1e-9 * a.suu.norm());
  for (int k = 0; k <= 96; ++k) {
    const Vec3 p = (*surface)->Position(k / 96.0, 0.5);
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 2.0, 2e-4) << k;
  }
  auto sheet = FlattenSurface(**surface, {49, 9});
  ASSERT_TRUE(sheet.ok()) << sheet.status().ToString();
  EXPECT_NEAR(sheet->period_u.norm(), 4.0 * kPi, 1e-4 * 4.0 * kPi);
  // Declared open, the natural spline is not C1 there.
  grid.periodic_u = false;
  auto natural = MakeSurface(grid);
  ASSERT_TRUE(natural.ok());
  EXPECT_GT(((*natural)->Evaluate(0.0, 0.3, 1).su - (*natural)->Evaluate(1.0, 0.3, 1).su).norm(),
            1e-3);
}

TEST(PeriodicFlatten, ALabelAllRoundABottleCloses) {
  // The NURBS bottle, periodic in u: a band exactly one period long round
  // its body, centred on the seam, closes: its two ends are one point.
  // The period is a translation: on a surface whose circumference varies
  // along v it is a compromise between them (here between the shoulder's
  // 2 pi 0.85 and the body's 2 pi).
  const BSplineSpec bottle = testing::NurbsBottle();
  auto surface = MakeSurface(bottle);
  ASSERT_TRUE(surface.ok()) << surface.status().ToString();
  auto sheet = FlattenSurface(**surface, {49, 25});
  ASSERT_TRUE(sheet.ok()) << sheet.status().ToString();
  const SheetMap map(**surface, *sheet);
  ASSERT_TRUE(map.periodic_u());
  const double period = sheet->period_u.norm();
  EXPECT_GT(period, 2.0 * kPi * 0.85);
  EXPECT_LT(period, 2.0 * kPi);
  const int n = 96;
  Mesh band = testing::FlatGrid(-period / 2, -0.1, period, 0.2, n, 2, 0.0);
  const Eigen::Rotation2Dd along(std::atan2(sheet->period_u.y(), sheet->period_u.x()));
  for (Vec3& q : band.positions) q.head<2>() = along * Vec2(q.head<2>());
  const Vec2 seam = map.SheetPoint(map.MapParameters(Vec2(0.0, 0.375)));
  auto r = Deform(SheetMap(**surface, *sheet), Mesh(band),
                  {.placement = testing::KeepCoordinates(band, seam), .subdivision = Off()});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->stats.outside, 0u);
  EXPECT_NEAR(r->stats.turns, 1.0, 1e-9);
  const std::vector<Vec3>& p = r->mesh.positions;
  for (int row = 0; row <= 2; ++row) {
    const size_t first = static_cast<size_t>(row) * (n + 1), last = first + n;
    EXPECT_LT((p[first] - p[last]).norm(), 1e-9) << "row " << row;
  }
  // On the body, a cylinder of radius 1 there.
  for (const Vec3& q : p) EXPECT_NEAR(std::hypot(q.x(), q.y()), 1.0, 1e-9);
}

TEST(PeriodicFlatten, AWholeTorusIsAFlatTorus) {
  // Periodic both ways: two periods, the last column the first a T_u on, the
  // last row the first a T_v on. The tube's circles (v) are all 2 pi r long,
  // so T_v is about that; T_u lies between the inner and outer equators.
  FlattenOptions o;
  o.tolerance = 1e-10;
  const Flat f = FlattenSpec(TorusSpec{3.0, 1.0, 0.0, 360.0, 0.0, 360.0, {}}, 49, 25, o);
  ASSERT_FALSE(f.sheet.period_u.isZero());
  ASSERT_FALSE(f.sheet.period_v.isZero());
  EXPECT_EQ(f.sheet.quality.folded_cells, 0);
  EXPECT_GT(f.sheet.period_u.norm(), 2.0 * kPi * 2.0);
  EXPECT_LT(f.sheet.period_u.norm(), 2.0 * kPi * 4.0);
  EXPECT_NEAR(f.sheet.period_v.norm(), 2.0 * kPi, 0.2 * 2.0 * kPi);
  const int nu = 49, nv = 25;
  for (int j = 0; j < nv; ++j) {
    EXPECT_LT((f.sheet.flat[48 + nu * j] - f.sheet.flat[nu * j] - f.sheet.period_u).norm(), 1e-12);
  }
  for (int i = 0; i < nu; ++i) {
    EXPECT_LT((f.sheet.flat[i + nu * 24] - f.sheet.flat[i] - f.sheet.period_v).norm(), 1e-12);
  }
}

// Distance from the tube's centre circle (radius 3 about +Z): 1 on the torus.
double OffTube(const Vec3& p) { return std::hypot(std::hypot(p.x(), p.y()) - 3.0, p.z()); }

TEST(PeriodicFlatten, ABandRoundATubeCrossesItsSeamInV) {
  // A quarter of a torus, closed round its tube only: periodic in v. A band
  // once round the tube, centred on the seam, closes, and lies on the tube.
  const Flat f = FlattenSpec(TorusSpec{3.0, 1.0, 0.0, 90.0, 0.0, 360.0, {}}, 17, 33);
  EXPECT_TRUE(f.sheet.period_u.isZero());
  ASSERT_FALSE(f.sheet.period_v.isZero());
  EXPECT_EQ(f.sheet.quality.folded_cells, 0);
  const SheetMap map(*f.surface, f.sheet);
  EXPECT_FALSE(map.periodic_u());
  ASSERT_TRUE(map.periodic_v());
  const double period = f.sheet.period_v.norm();
  const int n = 64;
  Mesh band = testing::FlatGrid(-0.2, -period / 2, 0.4, period, 2, n, 0.0);
  const Eigen::Rotation2Dd along(std::atan2(f.sheet.period_v.y(), f.sheet.period_v.x()) - kPi / 2);
  for (Vec3& q : band.positions) q.head<2>() = along * Vec2(q.head<2>());
  const Vec2 seam = map.SheetPoint(map.MapParameters(Vec2(0.5, 0.0)));
  auto r = Deform(SheetMap(*f.surface, f.sheet), Mesh(band),
                  {.placement = testing::KeepCoordinates(band, seam), .subdivision = Off()});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->stats.outside, 0u);
  EXPECT_NEAR(r->stats.turns, 1.0, 1e-9);
  for (const Vec3& q : r->mesh.positions) EXPECT_NEAR(OffTube(q), 1.0, 1e-9);
  for (int column = 0; column <= 2; ++column) {  // the ends of each line along the band meet
    const Vec3 first = r->mesh.positions[static_cast<size_t>(column)];
    const Vec3 last = r->mesh.positions[static_cast<size_t>(column + 3 * n)];
    EXPECT_LT((first - last).norm(), 1e-9) << column;
  }
  // Longer than the tube's round: fit stops at one turn.
  PlacementOptions fit = testing::KeepCoordinates(band, seam);
  fit.fit = true;
  auto fitted =
      Deform(SheetMap(*f.surface, f.sheet), Mesh(band), {.placement = fit, .subdivision = Off()});
  ASSERT_TRUE(fitted.ok()) << fitted.status().ToString();
  EXPECT_LE(fitted->stats.turns, 1.0);
  EXPECT_GT(fitted->stats.turns, 0.99);
}

TEST(PeriodicFlatten, GlyphsAcrossBothSeamsOfAWholeTorus) {
  // The flat torus continued past both seams: glyphs round the ring through
  // the corner where the two seams cross keep their shape and stand on it.
  const Flat f = FlattenSpec(TorusSpec{3.0, 1.0, 0.0, 360.0, 0.0, 360.0, {}}, 49, 25);
  const SheetMap map(*f.surface, f.sheet);
  ASSERT_TRUE(map.periodic_u());
  ASSERT_TRUE(map.periodic_v());
  RigidGlyphsRound(f, Vec2(0.0, 0.0));
  const Vec2 corner = map.SheetPoint(map.MapParameters(Vec2(0.0, 0.0)));
  // A plain band across the corner lies on the torus.
  const Mesh band = testing::FlatGrid(-1.0, -1.0, 2.0, 2.0, 8, 8, 0.0);
  auto b = Deform(SheetMap(*f.surface, f.sheet), Mesh(band),
                  {.placement = testing::KeepCoordinates(band, corner), .subdivision = Off()});
  ASSERT_TRUE(b.ok()) << b.status().ToString();
  for (const Vec3& q : b->mesh.positions) EXPECT_NEAR(OffTube(q), 1.0, 1e-9);
}

TEST(PeriodicFlatten, AGridClosedBothWaysIsAFlatTorus) {
  // A whole torus given as a grid of points, its last column and last row
  // repeating the first: periodic_u and periodic_v make it C2 all round and
  // flatten it with two periods.
  GridSpec grid;
  grid.nu = 25;
  grid.nv = 13;
  for (int j = 0; j < grid.nv; ++j) {
    for (int i = 0; i < grid.nu; ++i) {
      const double a = 2.0 * kPi * (i % 24) / 24, b = 2.0 * kPi * (j % 12) / 12;
      grid.points.emplace_back((3.0 + std::cos(b)) * std::cos(a), (3.0 + std::cos(b)) * std::sin(a),
                               std::sin(b));
    }
  }
  grid.periodic_u = grid.periodic_v = true;
  EXPECT_TRUE(ClosesInV(grid));
  auto surface = MakeSurface(grid);
  ASSERT_TRUE(surface.ok()) << surface.status().ToString();
  ASSERT_TRUE((*surface)->ClosedInV());
  const SurfacePoint a = (*surface)->Evaluate(0.3, 0.0, 2), b = (*surface)->Evaluate(0.3, 1.0, 2);
  EXPECT_LT((a.p - b.p).norm(), 1e-12);
  EXPECT_LT((a.sv - b.sv).norm(), 1e-9 * a.sv.norm());
  auto sheet = FlattenSurface(**surface, {33, 17});
  ASSERT_TRUE(sheet.ok()) << sheet.status().ToString();
  EXPECT_FALSE(sheet->period_u.isZero());
  EXPECT_NEAR(sheet->period_v.norm(), 2.0 * kPi, 0.2 * 2.0 * kPi);
  // Its last row moved: 422 on periodic_v, with the gap.
  grid.points[grid.nu * (grid.nv - 1) + 5].z() += 0.25;
  auto open = MakeSurface(grid);
  ASSERT_FALSE(open.ok());
  EXPECT_EQ(open.status().field(), "periodic_v");
  EXPECT_NE(open.status().message().find("does not close in v"), std::string::npos);
  EXPECT_NE(open.status().message().find("fails to meet by 0.25 "), std::string::npos)
      << open.status().message();
}

}  // namespace
}  // namespace surfdeform
