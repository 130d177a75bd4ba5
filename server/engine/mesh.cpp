#include "engine/mesh.hpp"

namespace surfdeform {

std::string CheckMesh(const Mesh& m) {
  const size_t n = m.positions.size();
  auto bad_size = [n](size_t size) { return size != 0 && size != n; };
  if (bad_size(m.normals.size())) return "normals: one per vertex expected";
  if (bad_size(m.tangents.size())) return "tangents: one per vertex expected";
  if (bad_size(m.uv0.size())) return "uv0: one per vertex expected";
  if (bad_size(m.uv1.size())) return "uv1: one per vertex expected";
  if (bad_size(m.colors.size())) return "colors: one per vertex expected";
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    for (uint32_t v : m.triangles[t]) {
      if (v >= n) {
        return "triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) + " of " +
               std::to_string(n);
      }
    }
  }
  uint32_t next = 0;
  for (const MeshGroup& g : m.groups) {
    if (g.first_triangle != next) return "groups must cover the triangles in order";
    next += g.triangle_count;
  }
  if (!m.groups.empty() && next != m.triangles.size()) {
    return "groups must cover the triangles in order";
  }
  return {};
}

}  // namespace surfdeform
