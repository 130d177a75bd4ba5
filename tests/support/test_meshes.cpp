#include "support/test_meshes.hpp"

namespace surfdeform::testing {

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

}  // namespace surfdeform::testing
