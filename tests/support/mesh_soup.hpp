// Triangle soups for the tests of surfaces given as meshes: a grid over
// (s, t) in [0, 1]^2, jittered or not, mapped through any function.
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "engine/common/geometry_types.hpp"

namespace surfdeform::testing {

using SoupTriangles = std::vector<std::array<uint32_t, 3>>;

struct Soup {
  std::vector<Vec3> positions;
  SoupTriangles triangles;
  std::vector<Vec2> st;  // the parameters each vertex was made from
};

// An nx x ny grid over (s, t) in [0, 1]^2, interior points moved at random
// by up to `jitter` of a cell, split into triangles along alternating
// diagonals, mapped through `f`.
template <typename F>
Soup Grid(int nx, int ny, double jitter, unsigned seed, const F& f) {
  Soup m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-jitter, jitter);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      double s = static_cast<double>(i) / (nx - 1), t = static_cast<double>(j) / (ny - 1);
      if (i > 0 && i < nx - 1) s += uniform(rng) / (nx - 1);
      if (j > 0 && j < ny - 1) t += uniform(rng) / (ny - 1);
      m.st.emplace_back(s, t);
      m.positions.push_back(f(s, t));
    }
  }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(i + nx * j); };
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      if ((i + j) % 2 == 0) {
        m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      } else {
        m.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
        m.triangles.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  }
  return m;
}

}  // namespace surfdeform::testing
