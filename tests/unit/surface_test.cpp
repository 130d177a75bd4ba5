// Every surface kind: exact derivatives, orientation, and exact representations.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "engine/surface/surface_spec.hpp"
#include "support/surface_file.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

constexpr double kPi = std::numbers::pi;

std::unique_ptr<Surface> Make(const SurfaceSpec& spec) { return testing::MakeValid(spec); }

struct KindCase {
  std::string name;
  SurfaceSpec spec;
};

std::vector<KindCase> AllKinds() {
  BSplineSpec bspline;
  bspline.degree_u = 3;
  bspline.degree_v = 2;
  bspline.count_u = 5;
  bspline.count_v = 4;
  bspline.knots_u = {0, 0, 0, 0, 0.4, 1, 1, 1, 1};
  bspline.knots_v = {0, 0, 0, 0.5, 1, 1, 1};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i)
      bspline.control_points.emplace_back(i, j, std::sin(i + 2.0 * j) * 0.7);
  GridSpec grid;
  grid.nu = 6;
  grid.nv = 5;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 6; ++i) grid.points.emplace_back(i * 0.5, j * 0.4, std::cos(i * 0.9 + j));
  Frame tilted;
  tilted.origin = Vec3(1, -2, 0.5);
  tilted.x_axis = Vec3(1, 1, 0);
  tilted.z_axis = Vec3(0.2, -0.1, 1);
  return {
      {"bezier", testing::LoadBezierFile(testing::DataPath("figure10.json"))},
      {"bspline", bspline},
      {"nurbs", testing::NurbsCone(1.0, 0.6, 1.5, 240.0)},
      {"cylinder", CylinderSpec{0.8, 2.0, 270.0, tilted}},
      {"cone", ConeSpec{1.0, 0.4, 1.2, 200.0, tilted}},
      {"sphere", SphereSpec{1.5, 10.0, 120.0, -60.0, 70.0, tilted}},
      {"torus", TorusSpec{2.0, 0.6, -30.0, 200.0, -120.0, 150.0, tilted}},
      {"wave", WaveSpec{4.0, 1.5, 0.3, 1.7, 0.8, 0.25, tilted}},
      {"grid", grid},
  };
}

// Names the case in test output instead of dumping its bytes.
void PrintTo(const KindCase& c, std::ostream* os) { *os << c.name; }

class EveryKind : public ::testing::TestWithParam<KindCase> {};

TEST_P(EveryKind, DerivativesMatchFiniteDifferences) {
  auto s = Make(GetParam().spec);
  const double h = 1e-5;
  // Away from knots (u = 0.4 and 0.5, v = 0.5), where splines are only C1.
  for (double u : {0.05, 0.37, 0.62, 0.81}) {
    for (double v : {0.1, 0.44, 0.93}) {
      const SurfacePoint p = s->Evaluate(u, v, 2);
      const SurfacePoint pu1 = s->Evaluate(u + h, v, 1), pu0 = s->Evaluate(u - h, v, 1);
      const SurfacePoint pv1 = s->Evaluate(u, v + h, 1), pv0 = s->Evaluate(u, v - h, 1);
      const double scale = 1.0 + p.su.norm() + p.sv.norm() + p.suu.norm() + p.svv.norm();
      EXPECT_LT((p.su - (pu1.p - pu0.p) / (2 * h)).norm(), 1e-6 * scale) << u << "," << v;
      EXPECT_LT((p.sv - (pv1.p - pv0.p) / (2 * h)).norm(), 1e-6 * scale) << u << "," << v;
      EXPECT_LT((p.suu - (pu1.su - pu0.su) / (2 * h)).norm(), 1e-5 * scale) << u << "," << v;
      EXPECT_LT((p.svv - (pv1.sv - pv0.sv) / (2 * h)).norm(), 1e-5 * scale) << u << "," << v;
      EXPECT_LT((p.suv - (pv1.su - pv0.su) / (2 * h)).norm(), 1e-5 * scale) << u << "," << v;
      EXPECT_LT((p.suv - (pu1.sv - pu0.sv) / (2 * h)).norm(), 1e-5 * scale) << u << "," << v;
      // Lower orders report the same values.
      EXPECT_EQ(s->Evaluate(u, v, 0).p, p.p);
      EXPECT_EQ(s->Evaluate(u, v, 1).su, p.su);
    }
  }
}

TEST_P(EveryKind, ContinuesSmoothlyPastTheBorder) {
  auto s = Make(GetParam().spec);
  // Just outside [0,1] the surface continues its end polynomial / formula.
  for (double u : {0.0, 1.0}) {
    const SurfacePoint in = s->Evaluate(u, 0.5, 1);
    const double h = 1e-4 * (u == 0.0 ? -1 : 1);
    const Vec3 out = s->Evaluate(u + h, 0.5, 0).p;
    EXPECT_LT((out - (in.p + h * in.su)).norm(), 1e-6 * (1 + in.su.norm()));
  }
}

// The batched evaluation (four points to a vector on the bicubic Bezier
// patch) against one point at a time: the same values to rounding, every
// derivative up to the order asked for and zeros past it; each point's
// result independent of the points beside it in the batch; lower orders
// report the same values.
TEST_P(EveryKind, EvaluateManyMatchesEvaluate) {
  auto s = Make(GetParam().spec);
  std::vector<Vec2> uv;  // 11 points: two full vectors and a tail of three
  for (int k = 0; k < 11; ++k) uv.emplace_back(-0.05 + 0.11 * k, 1.04 - 0.097 * k);
  auto fields = [](const SurfacePoint& p) {
    return std::array<Vec3, 6>{p.p, p.su, p.sv, p.suu, p.suv, p.svv};
  };
  std::vector<SurfacePoint> highest(uv.size());
  s->EvaluateMany(uv, 2, highest);
  for (int order = 0; order <= 2; ++order) {
    std::vector<SurfacePoint> many(uv.size());
    s->EvaluateMany(uv, order, many);
    for (size_t k = 0; k < uv.size(); ++k) {
      const SurfacePoint one = s->Evaluate(uv[k].x(), uv[k].y(), order);
      const auto want = fields(one), got = fields(many[k]);
      const double scale = 1.0 + one.p.norm() + one.su.norm() + one.sv.norm() + one.suu.norm() +
                           one.suv.norm() + one.svv.norm();
      for (int f = 0; f < 6; ++f) {
        EXPECT_LT((got[f] - want[f]).norm(), 1e-13 * scale)
            << "order " << order << ", point " << k << ", field " << f;
        if (f > (order == 0 ? 0 : order == 1 ? 2 : 5)) {
          EXPECT_EQ(got[f], Vec3::Zero());
        }
      }
      SurfacePoint alone;
      s->EvaluateMany(std::span(&uv[k], 1), order, std::span(&alone, 1));
      EXPECT_EQ(fields(alone), got) << "order " << order << ", point " << k;
      EXPECT_EQ(many[k].p, highest[k].p);
      if (order >= 1) {
        EXPECT_EQ(many[k].su, highest[k].su);
      }
    }
  }
}

// The positions moved along the normal in a batch (four to a vector on the
// bicubic Bezier patch, without the derivatives leaving the registers)
// against OffsetAlongNormal one point at a time: the same to rounding,
// heights of either sign and zero, and each point independent of its
// neighbours in the batch.
TEST_P(EveryKind, OffsetManyMatchesOffsetAlongNormal) {
  auto s = Make(GetParam().spec);
  std::vector<Vec2> uv;  // 11 points: two full vectors and a tail of three
  std::vector<double> h;
  for (int k = 0; k < 11; ++k) {
    uv.emplace_back(-0.05 + 0.11 * k, 1.04 - 0.097 * k);
    h.push_back(k == 4 ? 0.0 : 0.37 * std::sin(1.3 * k + 0.2));
  }
  std::vector<Vec3> many(uv.size());
  s->OffsetMany(uv, h, many);
  for (size_t k = 0; k < uv.size(); ++k) {
    const SurfacePoint one = s->Evaluate(uv[k].x(), uv[k].y(), 1);
    const Vec3 want = OffsetAlongNormal(one, h[k]);
    EXPECT_LT((many[k] - want).norm(), 1e-13 * (1.0 + one.p.norm() + std::abs(h[k])))
        << "point " << k;
    EXPECT_GT(std::abs(h[k]) > 0 ? (many[k] - one.p).norm() : 1.0, 0.9 * std::abs(h[k]))
        << "point " << k << " did not move by its height";
    Vec3 alone;
    s->OffsetMany(std::span(&uv[k], 1), std::span(&h[k], 1), std::span(&alone, 1));
    EXPECT_EQ(alone, many[k]) << "point " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, EveryKind, ::testing::ValuesIn(AllKinds()),
                         [](const auto& param_info) { return param_info.param.name; });

TEST(Surface, KindNames) {
  for (const KindCase& k : AllKinds()) EXPECT_EQ(Make(k.spec)->Kind(), k.name);
}

TEST(Surface, CylinderFollowsTheConventions) {
  auto s = Make(CylinderSpec{2.0, 3.0, 90.0, {}});
  // u: angle from +X towards +Y; v: height along +Z; normal away from the axis.
  EXPECT_LT((s->Position(0, 0) - Vec3(2, 0, 0)).norm(), 1e-15);
  EXPECT_LT((s->Position(1, 0) - Vec3(0, 2, 0)).norm(), 1e-15);
  EXPECT_LT((s->Position(0, 1) - Vec3(2, 0, 3)).norm(), 1e-15);
  EXPECT_LT((UnitNormal(s->Evaluate(0.5, 0.5, 1)) - Vec3(1, 1, 0).normalized()).norm(), 1e-15);
}

TEST(Surface, FrameMovesAndTurnsTheSurface) {
  Frame f;
  f.origin = Vec3(5, 0, 0);
  f.x_axis = Vec3(0, 1, 0);  // local +X is world +Y
  f.z_axis = Vec3(0, 0, 2);  // need not be unit length
  auto s = Make(CylinderSpec{1.0, 1.0, 180.0, f});
  EXPECT_LT((s->Position(0, 0) - Vec3(5, 1, 0)).norm(), 1e-15);
  EXPECT_LT((s->Position(0, 1) - Vec3(5, 1, 1)).norm(), 1e-15);
}

TEST(Surface, SphereAndTorusNormalsPointOutward) {
  auto sphere = Make(SphereSpec{2.0, 0, 90, -45, 45, {}});
  auto torus = Make(TorusSpec{3.0, 1.0, 0, 90, -90, 90, {}});
  for (double u : {0.2, 0.7}) {
    for (double v : {0.1, 0.5, 0.9}) {
      const SurfacePoint p = sphere->Evaluate(u, v, 1);
      EXPECT_NEAR(UnitNormal(p).dot(p.p.normalized()), 1.0, 1e-12);
      EXPECT_NEAR(p.p.norm(), 2.0, 1e-12);
      const SurfacePoint q = torus->Evaluate(u, v, 1);
      const Vec3 centre = Vec3(q.p.x(), q.p.y(), 0).normalized() * 3.0;
      EXPECT_NEAR(UnitNormal(q).dot((q.p - centre).normalized()), 1.0, 1e-12);
      EXPECT_NEAR((q.p - centre).norm(), 1.0, 1e-12);
    }
  }
}

TEST(Surface, NurbsRepresentsTheConeExactly) {
  const double r0 = 1.0, r1 = 0.6, h = 1.5;
  auto s = Make(testing::NurbsCone(r0, r1, h, 240.0));
  for (int j = 0; j <= 10; ++j) {
    for (int i = 0; i <= 40; ++i) {
      const SurfacePoint p = s->Evaluate(i / 40.0, j / 10.0, 1);
      const double radius = std::hypot(p.p.x(), p.p.y());
      const double expected = r0 + (r1 - r0) * p.p.z() / h;
      EXPECT_NEAR(radius, expected, 1e-14);
      // Normal points away from the axis.
      EXPECT_GT(UnitNormal(p).dot(Vec3(p.p.x(), p.p.y(), 0)), 0.0);
    }
  }
  const double end_angle = std::atan2(s->Position(1, 0).y(), s->Position(1, 0).x());
  EXPECT_NEAR(end_angle, 240.0 * kPi / 180.0 - 2 * kPi, 1e-14);
}

TEST(Surface, NurbsRepresentsTheCylinderExactly) {
  auto s = Make(testing::NurbsCone(0.7, 0.7, 2.0, 360.0));
  for (int i = 0; i <= 60; ++i) {
    EXPECT_NEAR(std::hypot(s->Position(i / 60.0, 0.3).x(), s->Position(i / 60.0, 0.3).y()), 0.7,
                1e-14);
  }
  EXPECT_LT((s->Position(0, 0) - s->Position(1, 0)).norm(), 1e-14);  // closes
}

TEST(Surface, GridInterpolatesItsPointsAndIsC2) {
  GridSpec g;
  g.nu = 7;
  g.nv = 4;
  for (int j = 0; j < g.nv; ++j)
    for (int i = 0; i < g.nu; ++i)
      g.points.emplace_back(i, j * 1.3, std::sin(i * 0.8) * std::cos(j * 1.1));
  auto s = Make(g);
  for (int j = 0; j < g.nv; ++j) {
    for (int i = 0; i < g.nu; ++i) {
      EXPECT_LT((s->Position(i / 6.0, j / 3.0) - g.points[i + g.nu * j]).norm(), 1e-12);
    }
  }
  // Across an interior knot (u = 2/6) the second derivative is continuous.
  const double knot = 2.0 / 6.0, h = 1e-9;
  const SurfacePoint a = s->Evaluate(knot - h, 0.4, 2), b = s->Evaluate(knot + h, 0.4, 2);
  EXPECT_LT((a.suu - b.suu).norm(), 1e-6 * (1 + a.suu.norm()));
}

// Where the normal vanishes (a Bezier patch whose first row of control
// points is one point: S_u = 0 along v = 0) the batch answers NaN, for the
// map to report, in a full vector of four and alone; the points beside it
// are unaffected.
TEST(Surface, OffsetManyIsNaNWhereTheNormalVanishes) {
  BezierSpec b;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      b.control_points.emplace_back(j == 0 ? 0.0 : i - 1.5, j, 0.1 * i * j);
  auto s = Make(b);
  const std::vector<Vec2> uv = {{0.2, 0.5}, {0.5, 0.0}, {0.7, 0.3}, {0.9, 0.8}};
  const std::vector<double> h = {0.1, 0.1, -0.2, 0.0};
  std::vector<Vec3> out(uv.size());
  s->OffsetMany(uv, h, out);
  EXPECT_TRUE(out[0].allFinite());
  EXPECT_FALSE(out[1].allFinite());
  EXPECT_TRUE(out[2].allFinite());
  EXPECT_TRUE(out[3].allFinite());
  Vec3 alone;
  s->OffsetMany(std::span(&uv[1], 1), std::span(&h[1], 1), std::span(&alone, 1));
  EXPECT_FALSE(alone.allFinite());
}

TEST(Surface, PlanarBezierIsItsBilinearMap) {
  BezierSpec b;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) b.control_points.emplace_back(2.0 * i / 3, 1.0 * j / 3, 0.0);
  auto s = Make(b);
  EXPECT_LT((s->Position(0.25, 0.6) - Vec3(0.5, 0.6, 0)).norm(), 1e-15);
  EXPECT_LT((UnitNormal(s->Evaluate(0.3, 0.3, 1)) - Vec3::UnitZ()).norm(), 1e-15);
}

}  // namespace
}  // namespace surfdeform

namespace surfdeform {
namespace {

TEST(Surface, InverseUnrollingInvertsTheUnrolling) {
  // A flat cone (unrolled sector wider than a half turn) and a cylinder.
  for (const SurfaceSpec& spec : {SurfaceSpec(ConeSpec{2.0, 0.2, 0.3, 350.0, {}}),
                                  SurfaceSpec(ConeSpec{0.5, 1.5, 2.0, 120.0, {}}),
                                  SurfaceSpec(CylinderSpec{1.5, 2.0, 300.0, {}})}) {
    auto s = testing::MakeValid(spec);
    for (double u : {-0.01, 0.0, 0.3, 0.99, 1.01}) {  // the 345-degree sector: only just past it
      for (double v : {-0.05, 0.0, 0.5, 1.0}) {
        const Vec2 flat = *s->ExactUnrolling(u, v);
        const Vec2 back = *s->InverseUnrolling(flat);
        EXPECT_LT((back - Vec2(u, v)).norm(), 1e-12) << s->Kind() << " " << u << "," << v;
      }
    }
  }
  EXPECT_FALSE(testing::MakeValid(WaveSpec{})->InverseUnrolling(Vec2(0, 0)).has_value());
}

}  // namespace
}  // namespace surfdeform
