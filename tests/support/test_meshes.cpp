#include "support/test_meshes.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

namespace surfdeform::testing {

PlacementOptions KeepCoordinates(const Mesh& m, const Vec2& at) {
  Eigen::AlignedBox3d box;
  for (const Vec3& p : m.positions) box.extend(p);
  PlacementOptions o;
  o.anchor = AnchorMode::kValue;
  o.anchor_value = 0.0;
  o.center_mode = CenterMode::kSheetUnits;
  o.center = at + 0.5 * (box.min() + box.max()).head<2>();
  return o;
}

Mesh ThinPlate(double size_x, double size_y, double thickness) {
  Mesh m;
  const double x = size_x / 2, y = size_y / 2, z = thickness / 2;
  m.positions = {{-x, -y, -z}, {x, -y, -z}, {x, y, -z}, {-x, y, -z},
                 {-x, -y, z},  {x, -y, z},  {x, y, z},  {-x, y, z}};
  const uint32_t quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

Mesh GlyphRow(int count, double length) {
  Mesh glyphs;
  for (int g = 0; g < count; ++g) {
    const Mesh box = ThinPlate(0.4, 0.6, 0.1);
    const Vec3 at(-length / 2 + length * (g + 0.5) / count, 0.0, 0.05);
    const uint32_t base = static_cast<uint32_t>(glyphs.positions.size());
    for (const Vec3& p : box.positions) glyphs.positions.push_back(p + at);
    for (const auto& tri : box.triangles) {
      glyphs.triangles.push_back({tri[0] + base, tri[1] + base, tri[2] + base});
    }
  }
  return glyphs;
}

double WorstGlyphStretch(const Mesh& before, const Mesh& after) {
  double worst = 0.0;
  for (size_t g = 0; 8 * g + 8 <= before.positions.size(); ++g) {
    for (size_t a = 8 * g; a < 8 * g + 8; ++a) {
      for (size_t b = a + 1; b < 8 * g + 8; ++b) {
        const double d0 = (before.positions[a] - before.positions[b]).norm();
        const double d1 = (after.positions[a] - after.positions[b]).norm();
        worst = std::max(worst, std::abs(d1 - d0) / d0);
      }
    }
  }
  return worst;
}

Mesh FlatGrid(double x0, double y0, double sx, double sy, int nx, int ny, double z) {
  Mesh m;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + sx * i / nx, y = y0 + sy * j / ny;
      m.positions.emplace_back(x, y, z);
      m.normals.emplace_back(0, 0, 1);
      m.tangents.emplace_back(1, 0, 0, 1);
      m.uv0.emplace_back(x, y);
      m.colors.emplace_back(static_cast<double>(i) / nx, static_cast<double>(j) / ny, 0.5, 1.0);
    }
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = i + (nx + 1) * j, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  }
  return m;
}

Mesh UvSphere(double radius, int slices, int stacks) {
  Mesh m;
  const double pi = std::numbers::pi;
  m.positions.emplace_back(0, 0, -radius);
  for (int j = 1; j < stacks; ++j) {
    const double phi = -pi / 2 + pi * j / stacks;
    for (int i = 0; i < slices; ++i) {
      const double theta = 2 * pi * i / slices;
      m.positions.emplace_back(radius * std::cos(phi) * std::cos(theta),
                               radius * std::cos(phi) * std::sin(theta), radius * std::sin(phi));
    }
  }
  m.positions.emplace_back(0, 0, radius);
  auto ring = [slices](int j, int i) {
    return static_cast<uint32_t>(1 + (j - 1) * slices + (i % slices));
  };
  const uint32_t top = static_cast<uint32_t>(m.positions.size() - 1);
  for (int i = 0; i < slices; ++i) {
    m.triangles.push_back({0, ring(1, i + 1), ring(1, i)});
    m.triangles.push_back({top, ring(stacks - 1, i), ring(stacks - 1, i + 1)});
    for (int j = 1; j + 1 < stacks; ++j) {
      m.triangles.push_back({ring(j, i), ring(j, i + 1), ring(j + 1, i + 1)});
      m.triangles.push_back({ring(j, i), ring(j + 1, i + 1), ring(j + 1, i)});
    }
  }
  return m;
}

std::string ClosedManifoldProblem(const Mesh& mesh) {
  using Key = std::tuple<double, double, double>;
  std::map<Key, int> ids;
  auto id = [&](uint32_t v) {
    const Vec3& p = mesh.positions[v];
    return ids.try_emplace(Key(p.x(), p.y(), p.z()), static_cast<int>(ids.size())).first->second;
  };
  std::map<std::pair<int, int>, int> directed;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const int w[3] = {id(tri[0]), id(tri[1]), id(tri[2])};
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) {
      return "triangle " + std::to_string(t) + " repeats a position";
    }
    for (int k = 0; k < 3; ++k) ++directed[{w[k], w[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return "a directed edge is used " + std::to_string(count) + " times";
    const auto back = directed.find({edge.second, edge.first});
    if (back == directed.end()) return "an edge has no opposite (a crack or a T-junction)";
  }
  return "";
}

}  // namespace surfdeform::testing
