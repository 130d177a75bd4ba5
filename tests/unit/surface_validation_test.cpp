// Bad surface specs give an error that names the field and says what is wrong.
#include <gtest/gtest.h>

#include <limits>
#include <ostream>
#include <string>

#include "engine/surface/surface_spec.hpp"

namespace surfdeform {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct BadSpec {
  std::string name;
  SurfaceSpec spec;
  ErrorCode code;
  std::string field;
  std::string says;  // a substring of the message
};

BezierSpec Bicubic() {
  BezierSpec b;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) b.control_points.emplace_back(i, j, (i * j) % 2);
  return b;
}

BSplineSpec Quadratic() {
  BSplineSpec s;
  s.degree_u = s.degree_v = 2;
  s.count_u = s.count_v = 4;
  s.knots_u = s.knots_v = {0, 0, 0, 0.5, 1, 1, 1};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) s.control_points.emplace_back(i, j, 0.1 * i * j);
  return s;
}

std::vector<BadSpec> Cases() {
  std::vector<BadSpec> c;
  {
    BezierSpec b = Bicubic();
    b.control_points[5].y() = kNaN;
    c.push_back({"BezierNaN", b, ErrorCode::kInvalidArgument, "control_points[5]", "finite"});
  }
  {
    BezierSpec b = Bicubic();
    b.control_points.pop_back();
    c.push_back({"BezierCount", b, ErrorCode::kInvalidArgument, "control_points", "needs 16"});
  }
  {
    BezierSpec b = Bicubic();
    b.degree_u = 16;
    c.push_back({"BezierDegree", b, ErrorCode::kInvalidArgument, "degree_u", "1 to 15"});
  }
  {
    BezierSpec b = Bicubic();
    for (Vec3& p : b.control_points) p = Vec3(1, 2, 3);
    c.push_back({"BezierCollapsed", b, ErrorCode::kDegenerate, "control_points", "coincide"});
  }
  {
    BSplineSpec s = Quadratic();
    s.degree_u = 8;
    c.push_back({"BSplineDegree", s, ErrorCode::kInvalidArgument, "degree_u", "1 to 7"});
  }
  {
    BSplineSpec s = Quadratic();
    s.knots_u = {0, 0, 0, 0.5, 1, 1};
    c.push_back({"KnotCount", s, ErrorCode::kInvalidArgument, "knots_u", "7 values"});
  }
  {
    BSplineSpec s = Quadratic();
    s.knots_v = {0, 0, 0, 0.7, 0.5, 1, 1};
    c.push_back({"KnotOrder", s, ErrorCode::kInvalidArgument, "knots_v[4]", "non-decreasing"});
  }
  {
    BSplineSpec s = Quadratic();
    s.knots_u = {0, 0, 0.1, 0.5, 1, 1, 1};
    c.push_back({"KnotNotClamped", s, ErrorCode::kInvalidArgument, "knots_u", "clamped"});
  }
  {
    BSplineSpec s = Quadratic();
    s.knots_u = {0, 0, 0, kInf, 1, 1, 1};
    c.push_back({"KnotInf", s, ErrorCode::kInvalidArgument, "knots_u[3]", "finite"});
  }
  {
    BSplineSpec s = Quadratic();
    s.rational = true;
    s.weights.assign(16, 1.0);
    s.weights[7] = -0.5;
    c.push_back({"NegativeWeight", s, ErrorCode::kInvalidArgument, "weights[7]", "greater than 0"});
  }
  {
    BSplineSpec s = Quadratic();
    s.rational = true;
    s.weights.assign(3, 1.0);
    c.push_back({"WeightCount", s, ErrorCode::kInvalidArgument, "weights", "one weight"});
  }
  {
    BSplineSpec s = Quadratic();
    s.weights.assign(16, 1.0);
    c.push_back({"WeightsOnBSpline", s, ErrorCode::kInvalidArgument, "weights", "nurbs"});
  }
  c.push_back({"ZeroRadius", CylinderSpec{0.0, 1.0, 90.0, {}}, ErrorCode::kInvalidArgument,
               "radius", "greater than 0"});
  c.push_back({"NaNHeight", CylinderSpec{1.0, kNaN, 90.0, {}}, ErrorCode::kInvalidArgument,
               "height", "finite"});
  c.push_back({"AngleOver360", CylinderSpec{1.0, 1.0, 361.0, {}}, ErrorCode::kInvalidArgument,
               "angle_deg", "[0, 360]"});
  c.push_back({"ConeLine", ConeSpec{0.0, 0.0, 1.0, 90.0, {}}, ErrorCode::kDegenerate,
               "radius_bottom", "both 0"});
  c.push_back({"ConeNegative", ConeSpec{1.0, -0.5, 1.0, 90.0, {}}, ErrorCode::kInvalidArgument,
               "radius_top", "negative"});
  c.push_back({"SphereLatitude", SphereSpec{1.0, 0, 90, -95, 45, {}}, ErrorCode::kInvalidArgument,
               "lat_min_deg", "[-90, 90]"});
  c.push_back({"SphereEmptyRange", SphereSpec{1.0, 50, 40, -45, 45, {}},
               ErrorCode::kInvalidArgument, "lon_max_deg", "greater than lon_min_deg"});
  c.push_back({"TorusSpan", TorusSpec{2.0, 0.5, 0, 400, 0, 90, {}}, ErrorCode::kInvalidArgument,
               "u_max_deg", "at most 360"});
  c.push_back({"WaveLength", WaveSpec{4.0, 1.0, 0.2, 0.0, 1.0, 0.0, {}},
               ErrorCode::kInvalidArgument, "wavelength", "greater than 0"});
  {
    Frame f;
    f.x_axis = Vec3(0, 0, 3);
    c.push_back({"ParallelFrame", CylinderSpec{1.0, 1.0, 90.0, f}, ErrorCode::kDegenerate,
                 "frame.x_axis", "parallel"});
  }
  {
    Frame f;
    f.origin = Vec3(0, kNaN, 0);
    c.push_back({"FrameNaN", WaveSpec{4.0, 1.0, 0.2, 2.0, 1.0, 0.0, f}, ErrorCode::kInvalidArgument,
                 "frame.origin", "finite"});
  }
  {
    GridSpec g;
    g.nu = 1;
    g.nv = 4;
    g.points.assign(4, Vec3::Zero());
    c.push_back({"GridTooSmall", g, ErrorCode::kInvalidArgument, "nu", "from 2"});
  }
  {
    GridSpec g;
    g.nu = 3;
    g.nv = 3;
    g.points.assign(8, Vec3(1, 0, 0));
    c.push_back({"GridCount", g, ErrorCode::kInvalidArgument, "points", "9 points expected"});
  }
  // Huge finite sizes overflow the derivatives: refused as too large, never
  // blamed on a vanishing normal (item 6).
  c.push_back({"HugeRadius", CylinderSpec{1e300, 1.0, 90.0, {}}, ErrorCode::kInvalidArgument,
               "radius", "within +-1e+15"});
  {
    BezierSpec b = Bicubic();
    b.control_points[5].z() = -2e15;
    c.push_back(
        {"HugeControlPoint", b, ErrorCode::kInvalidArgument, "control_points[5][2]", "got -2e+15"});
  }
  // A horn torus (tube radius = major radius) pinches at v = 180 degrees and
  // a spindle torus (tube past it) where R + r cos v = 0: refused from the
  // radii and the span, however the surface would be sampled.
  c.push_back({"HornTorus", TorusSpec{1.0, 1.0, 0, 360, -180, 180, {}}, ErrorCode::kDegenerate,
               "minor_radius", "reaches the axis"});
  c.push_back({"SpindleTorusPinchInTheSpan", TorusSpec{1.0, 2.0, 0, 90, 100, 130, {}},
               ErrorCode::kDegenerate, "minor_radius", "v = 120"});
  c.push_back({"SpindleTorusPinchOneTurnOn", TorusSpec{1.0, 2.0, 0, 90, 200, 250, {}},
               ErrorCode::kDegenerate, "minor_radius", "v = 240"});
  {
    Frame f;
    f.origin = Vec3(1e16, 0, 0);
    c.push_back({"HugeOrigin", TorusSpec{2.0, 0.5, 0, 90, 0, 90, f}, ErrorCode::kInvalidArgument,
                 "frame.origin[0]", "within"});
  }
  return c;
}

// Names the case in test output instead of dumping its bytes.
void PrintTo(const BadSpec& c, std::ostream* os) { *os << c.name; }

class BadSurface : public ::testing::TestWithParam<BadSpec> {};

TEST_P(BadSurface, IsRejectedWithFieldAndReason) {
  const BadSpec& b = GetParam();
  auto s = MakeSurface(b.spec);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), b.code) << s.status().ToString();
  EXPECT_EQ(s.status().field(), b.field) << s.status().ToString();
  EXPECT_NE(s.status().message().find(b.says), std::string::npos) << s.status().ToString();
}

INSTANTIATE_TEST_SUITE_P(Specs, BadSurface, ::testing::ValuesIn(Cases()),
                         [](const auto& param_info) { return param_info.param.name; });

// A fat torus whose v span keeps clear of the pinch is a surface like any
// other, and so is a ring torus at any span.
TEST(TorusAxis, ASpanClearOfThePinchIsAccepted) {
  EXPECT_TRUE(MakeSurface(TorusSpec{1.0, 2.0, 0, 90, -90, 90, {}}).ok());       // pinch at +-120
  EXPECT_TRUE(MakeSurface(TorusSpec{1.0, 0.999, 0, 360, -180, 180, {}}).ok());  // a ring torus
  EXPECT_FALSE(MakeSurface(TorusSpec{1.0, 2.0, 0, 90, -90, 121, {}}).ok());
}

TEST(Status, FieldPrefixJoinsPaths) {
  const Status s = InvalidArgument("bad", "control_points[3]");
  EXPECT_EQ(s.WithFieldPrefix("surface").field(), "surface.control_points[3]");
  EXPECT_EQ(InvalidArgument("bad", "[2]").WithFieldPrefix("points").field(), "points[2]");
  EXPECT_TRUE(Status::Ok().WithFieldPrefix("x").ok());
}

TEST(Result, HoldsAValueOrAnErrorNeverAnOkStatusWithoutAValue) {
  const Result<int> value = 3;
  EXPECT_TRUE(value.ok());
  EXPECT_TRUE(value.status().ok());
  const Result<int> error = InvalidArgument("bad", "x");
  EXPECT_FALSE(error.ok());
  EXPECT_EQ(error.status().code(), ErrorCode::kInvalidArgument);
  // An ok status stands for no value: an error, never "not ok, status OK".
  const Result<int> empty = Status::Ok();
  EXPECT_FALSE(empty.ok());
  EXPECT_EQ(empty.status().code(), ErrorCode::kInternal);
  EXPECT_EQ(Result<int>(NotComputed()).status().code(), ErrorCode::kInternal);
}

}  // namespace
}  // namespace surfdeform
