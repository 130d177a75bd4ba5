#include "part/part_body.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_set>
#include <vector>

#include "base/format.hpp"

namespace surfdeform {
namespace {

// The sample grid: `count` samples along a direction, its last one its
// first where the surface closes that way.
struct Axis {
  int count = 0;
  bool closed = false;
  int cells() const { return closed ? count : count - 1; }
  double at(int k) const {
    return closed ? static_cast<double>(k) / count : static_cast<double>(k) / (count - 1);
  }
  int next(int k) const { return closed ? (k + 1) % count : k + 1; }
};

// The principal curvatures at a surface point (second derivatives set),
// with the normal Su x Sv: k such that the offset by h along the normal is
// regular where 1 - h k > 0 for both.
std::array<double, 2> PrincipalCurvatures(const SurfacePoint& s, const Vec3& n) {
  const double e = s.su.dot(s.su), f = s.su.dot(s.sv), g = s.sv.dot(s.sv);
  const double l = s.suu.dot(n), m = s.suv.dot(n), nn = s.svv.dot(n);
  const double det = e * g - f * f;
  const double h = (e * nn + g * l - 2 * f * m) / (2 * det);
  const double k = (l * nn - m * m) / det;
  const double root = std::sqrt(std::max(0.0, h * h - k));
  return {h - root, h + root};
}

}  // namespace

std::array<int, 2> BodySamples(const Surface& surface, double step_deg, int most) {
  constexpr int kProbe = 33;
  std::vector<Vec3> n(kProbe * kProbe);
  for (int j = 0; j < kProbe; ++j) {
    for (int i = 0; i < kProbe; ++i) {
      n[j * kProbe + i] = UnitNormal(surface.Evaluate(i / (kProbe - 1.0), j / (kProbe - 1.0), 1));
    }
  }
  auto angle = [](const Vec3& a, const Vec3& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b));  // 0 where either normal vanishes
  };
  double turn_u = 0, turn_v = 0;
  for (int r = 0; r < kProbe; ++r) {
    double along_u = 0, along_v = 0;
    for (int k = 0; k + 1 < kProbe; ++k) {
      along_u += angle(n[r * kProbe + k], n[r * kProbe + k + 1]);
      along_v += angle(n[k * kProbe + r], n[(k + 1) * kProbe + r]);
    }
    turn_u = std::max(turn_u, along_u);
    turn_v = std::max(turn_v, along_v);
  }
  const double step = step_deg * std::numbers::pi / 180;
  auto samples = [&](double turn, bool closed) {
    const int steps = static_cast<int>(std::ceil(turn / step - 1e-9));
    return std::clamp(closed ? std::max(steps, 3) : steps + 1, 2, most);
  };
  return {samples(turn_u, surface.ClosedInU()), samples(turn_v, surface.ClosedInV())};
}

std::array<double, 2> BodyHeights(const BodyOptions& o) {
  switch (o.side) {
    case BodySide::kInside:
      return {-o.thickness, 0.0};
    case BodySide::kBoth:
      return {-o.thickness / 2, o.thickness / 2};
    case BodySide::kOutside:
      break;
  }
  return {0.0, o.thickness};
}

size_t BodyTriangles(const Surface& surface, const BodyOptions& o) {
  const Axis u{o.nu, surface.ClosedInU()}, v{o.nv, surface.ClosedInV()};
  const size_t cu = static_cast<size_t>(std::max(0, u.cells()));
  const size_t cv = static_cast<size_t>(std::max(0, v.cells()));
  size_t walls = 0;
  if (!u.closed) walls += 2 * cv;
  if (!v.closed) walls += 2 * cu;
  return 4 * cu * cv + 2 * walls;
}

Result<Mesh> ThickenSurface(const Surface& surface, const BodyOptions& o) {
  if (!(o.thickness > 0) || !std::isfinite(o.thickness)) {
    return Status(
        ErrorCode::kInvalidArgument,
        Format("the body's thickness must be a positive number of mm, got %g", o.thickness),
        "body.thickness_mm");
  }
  if (o.nu < 2 || o.nv < 2) {
    return Status(ErrorCode::kInvalidArgument,
                  Format("a body needs at least 2 x 2 samples, got %d x %d", o.nu, o.nv),
                  "sampling");
  }
  if (surface.flat_mesh() != nullptr) {
    return Status(ErrorCode::kInvalidArgument,
                  "a body is made from a parametric surface; a surface given as a mesh has no "
                  "parameters to thicken it by",
                  "surface");
  }
  const Axis u{o.nu, surface.ClosedInU()}, v{o.nv, surface.ClosedInV()};
  const auto [lo, hi] = BodyHeights(o);
  const size_t per_layer = static_cast<size_t>(u.count) * static_cast<size_t>(v.count);
  Mesh mesh;
  mesh.positions.resize(2 * per_layer);
  // The thickness each side can take before its face folds (1 - h k > 0).
  double room_high = std::numeric_limits<double>::infinity();
  double room_low = std::numeric_limits<double>::infinity();
  Vec2 tightest_high(0, 0), tightest_low(0, 0);
  for (int j = 0; j < v.count; ++j) {
    for (int i = 0; i < u.count; ++i) {
      const double pu = u.at(i), pv = v.at(j);
      const SurfacePoint s = surface.Evaluate(pu, pv, 2);
      const Vec3 n = UnitNormal(s);
      // A normal that rounding alone makes (at a pole, Su is ~1e-16 long).
      const double scale = s.su.squaredNorm() + s.sv.squaredNorm();
      if (n.isZero() || !s.p.allFinite() || !(s.su.cross(s.sv).norm() > 1e-9 * scale)) {
        return Degenerate(Format("the surface has no normal at (u, v) = (%.4g, %.4g): a body "
                                 "cannot be grown from a pole or a collapsed edge",
                                 pu, pv),
                          "surface");
      }
      for (double k : PrincipalCurvatures(s, n)) {
        if (k > 0 && 1 / k < room_high) room_high = 1 / k, tightest_high = Vec2(pu, pv);
        if (k < 0 && -1 / k < room_low) room_low = -1 / k, tightest_low = Vec2(pu, pv);
      }
      const size_t at = static_cast<size_t>(j) * u.count + i;
      mesh.positions[at] = s.p + lo * n;
      mesh.positions[per_layer + at] = s.p + hi * n;
    }
  }
  // The offset face folds where 1 - h k reaches 0; a margin keeps its
  // triangles from collapsing near there.
  constexpr double kMargin = 0.95;
  const double high = std::max(hi, 0.0), low = std::max(-lo, 0.0);
  if (high > kMargin * room_high || low > kMargin * room_low) {
    const bool high_side = high > kMargin * room_high;
    const Vec2 at = high_side ? tightest_high : tightest_low;
    const double room = (high_side ? room_high : room_low) * kMargin;
    const double largest = o.side == BodySide::kBoth ? 2 * room : room;
    return Status(ErrorCode::kDegenerate,
                  Format("a body %g mm thick %s the surface folds over itself: the surface bends "
                         "with a radius of %.4g mm at (u, v) = (%.3g, %.3g); the largest thickness "
                         "there is %.4g mm",
                         o.thickness, high_side ? "along the normal of" : "against the normal of",
                         high_side ? room_high : room_low, at.x(), at.y(), largest),
                  "body.thickness_mm")
        .WithLimit(largest, o.thickness);
  }
  auto index = [&](int layer, int i, int j) {
    return static_cast<uint32_t>(layer * per_layer + static_cast<size_t>(j) * u.count + i);
  };
  mesh.triangles.reserve(BodyTriangles(surface, o));
  // The skins: the high face's normal along Su x Sv (outward), the low face's against it.
  for (int j = 0; j < v.cells(); ++j) {
    for (int i = 0; i < u.cells(); ++i) {
      const int i1 = u.next(i), j1 = v.next(j);
      for (int layer : {0, 1}) {
        const uint32_t a = index(layer, i, j), b = index(layer, i1, j), c = index(layer, i1, j1),
                       d = index(layer, i, j1);
        if (layer == 1) {
          mesh.triangles.push_back({a, b, c});
          mesh.triangles.push_back({a, c, d});
        } else {
          mesh.triangles.push_back({a, c, b});
          mesh.triangles.push_back({a, d, c});
        }
      }
    }
  }
  // The walls: along each edge x -> y of the high skin that no other high
  // triangle shares (an open border), the quad down to the low skin, wound
  // so that every edge is shared by two triangles in opposite directions.
  const size_t skins = mesh.triangles.size();
  std::unordered_set<uint64_t> high_edges;
  auto key = [](uint32_t x, uint32_t y) { return (static_cast<uint64_t>(x) << 32) | y; };
  for (size_t t = 0; t < skins; ++t) {
    const auto& tri = mesh.triangles[t];
    if (tri[0] < per_layer) continue;
    for (int e = 0; e < 3; ++e) high_edges.insert(key(tri[e], tri[(e + 1) % 3]));
  }
  const auto low_of = [&](uint32_t x) { return static_cast<uint32_t>(x - per_layer); };
  for (size_t t = 0; t < skins; ++t) {
    const auto tri = mesh.triangles[t];
    if (tri[0] < per_layer) continue;
    for (int e = 0; e < 3; ++e) {
      const uint32_t x = tri[e], y = tri[(e + 1) % 3];
      if (high_edges.count(key(y, x))) continue;
      mesh.triangles.push_back({y, x, low_of(x)});
      mesh.triangles.push_back({y, low_of(x), low_of(y)});
    }
  }
  return mesh;
}

}  // namespace surfdeform
