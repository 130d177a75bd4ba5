// Small helpers shared by the subdivision's stage tests.
#pragma once

#include "engine/surface/surface_spec.hpp"
#include "support/subdivision_stages.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform::testing {

inline BezierSpec PlaneSpec() {  // the square [0, 2]^2 at z = 0
  BezierSpec plane;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) plane.control_points.emplace_back(2.0 * i / 3, 2.0 * j / 3, 0.0);
  return plane;
}

inline Target Cylinder(double radius, int n = 16) {
  return Flattened(CylinderSpec{radius, 2.0, 180.0, {}}, n);
}

// The paper's Figure 8-10 Bezier surface, sampled n x n.
inline Target Figure(int number, int n) {
  return Flattened(LoadBezierFile(DataPath("figure" + std::to_string(number) + ".json")), n);
}

inline SubdivisionOptions Tolerance(double t) {
  SubdivisionOptions s;
  s.tolerance = t;
  return s;
}

// The plate with its own three vertices per triangle (every edge a seam).
inline Mesh Unwelded(const Mesh& m) {
  Mesh out;
  for (const auto& t : m.triangles) {
    const uint32_t base = static_cast<uint32_t>(out.positions.size());
    for (int k = 0; k < 3; ++k) out.positions.push_back(m.positions[t[k]]);
    out.triangles.push_back({base, base + 1, base + 2});
  }
  return out;
}

}  // namespace surfdeform::testing
