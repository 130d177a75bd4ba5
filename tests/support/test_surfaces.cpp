#include "support/test_surfaces.hpp"

#include "support/expect_ok.hpp"

#include <cmath>
#include <numbers>

namespace surfdeform::testing {

std::unique_ptr<Surface> MakeValid(const SurfaceSpec& spec) {
  auto s = MakeSurface(spec);
  ExpectOk(s);
  return s.ok() ? std::move(s).value() : nullptr;
}

BSplineSpec NurbsRevolution(const std::vector<Vec2>& profile, int degree_v,
                            const std::vector<double>& knots_v, double angle_deg) {
  const int arcs = static_cast<int>(std::ceil(angle_deg / 120.0 - 1e-9));
  const double step = angle_deg / arcs * std::numbers::pi / 180.0;
  BSplineSpec s;
  s.rational = true;
  s.degree_u = 2;
  s.degree_v = degree_v;
  s.count_u = 2 * arcs + 1;
  s.count_v = static_cast<int>(profile.size());
  s.knots_u = {0, 0, 0};
  for (int a = 1; a < arcs; ++a) {
    s.knots_u.push_back(static_cast<double>(a) / arcs);
    s.knots_u.push_back(static_cast<double>(a) / arcs);
  }
  s.knots_u.insert(s.knots_u.end(), {1, 1, 1});
  s.knots_v = knots_v;
  for (const Vec2& rz : profile) {
    for (int k = 0; k < s.count_u; ++k) {
      const double theta = k * step / 2;
      const bool middle = k % 2 == 1;
      const double scale = middle ? 1.0 / std::cos(step / 2) : 1.0;
      const double r = rz.x();
      s.control_points.emplace_back(r * scale * std::cos(theta), r * scale * std::sin(theta),
                                    rz.y());
      s.weights.push_back(middle ? std::cos(step / 2) : 1.0);
    }
  }
  s.periodic_u = angle_deg >= 360.0;
  return s;
}

BSplineSpec NurbsCone(double r0, double r1, double h, double angle_deg) {
  BSplineSpec s = NurbsRevolution({Vec2(r0, 0.0), Vec2(r1, h)}, 1, {0, 0, 1, 1}, angle_deg);
  s.periodic_u = false;
  return s;
}

BSplineSpec NurbsBottle() {
  // (radius, height), as client/web/samples/bottle.json.
  const std::vector<Vec2> profile = {{0.95, 0.0}, {1.0, 0.4}, {1.0, 1.0}, {1.0, 1.6},
                                     {1.0, 2.2},  {0.9, 2.6}, {0.85, 2.8}};
  return NurbsRevolution(profile, 3, {0, 0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1, 1}, 360.0);
}

Target Flattened(const SurfaceSpec& spec, int n) {
  Target t;
  t.surface = MakeValid(spec);
  if (t.surface == nullptr) return t;
  auto r = FlattenSurface(*t.surface, {n, n});
  ExpectOk(r);
  if (r.ok()) t.sheet = std::move(r).value();
  return t;
}

BSplineSpec BumpOnAPlane(double height) {
  BSplineSpec s;
  s.count_u = s.count_v = 10;
  for (int k = 0; k < 4; ++k) s.knots_u.push_back(0.0);
  for (int k = 1; k <= 6; ++k) s.knots_u.push_back(k / 7.0);
  for (int k = 0; k < 4; ++k) s.knots_u.push_back(1.0);
  s.knots_v = s.knots_u;
  for (int j = 0; j < 10; ++j) {
    for (int i = 0; i < 10; ++i) {
      const bool bump = i >= 6 && i <= 7 && j >= 6 && j <= 7;
      s.control_points.emplace_back(2.0 * i / 9, 2.0 * j / 9, bump ? height : 0.0);
    }
  }
  return s;
}

GridSpec GridCylinder(double radius, double height, double angle_deg, int nu, int nv) {
  GridSpec g;
  g.nu = nu;
  g.nv = nv;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double theta = angle_deg * std::numbers::pi / 180.0 * i / (nu - 1);
      g.points.emplace_back(radius * std::cos(theta), radius * std::sin(theta),
                            height * j / (nv - 1));
    }
  }
  return g;
}

}  // namespace surfdeform::testing
