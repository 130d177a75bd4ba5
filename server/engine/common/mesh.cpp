#include "engine/common/mesh.hpp"

#include <algorithm>

namespace surfdeform {

std::string CheckMesh(const Mesh& m) {
  const size_t n = m.positions.size();
  auto bad_size = [n](size_t size) { return size != 0 && size != n; };
  if (bad_size(m.normals.size())) return "normals: one per vertex expected";
  if (bad_size(m.tangents.size())) return "tangents: one per vertex expected";
  if (bad_size(m.uv0.size())) return "uv0: one per vertex expected";
  if (bad_size(m.uv1.size())) return "uv1: one per vertex expected";
  if (bad_size(m.colors.size())) return "colors: one per vertex expected";
  if (bad_size(m.distortion.size())) return "distortion: one per vertex expected";
  // The largest index first (a loop the compiler vectorises: this runs on
  // every request, three times), the culprit only when there is one.
  uint32_t largest = 0;
  for (const auto& t : m.triangles) largest = std::max({largest, t[0], t[1], t[2]});
  if (largest >= n) {
    for (size_t t = 0; t < m.triangles.size(); ++t) {
      for (uint32_t v : m.triangles[t]) {
        if (v >= n) {
          return "triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) + " of " +
                 std::to_string(n);
        }
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

void ComputeVertexNormals(Mesh* mesh) {
  mesh->normals.assign(mesh->positions.size(), Vec3::Zero());
  for (const auto& t : mesh->triangles) {
    const Vec3& a = mesh->positions[t[0]];
    // The cross product's length is twice the area: area weighting for free.
    const Vec3 n = (mesh->positions[t[1]] - a).cross(mesh->positions[t[2]] - a);
    for (uint32_t v : t) mesh->normals[v] += n;
  }
  for (Vec3& n : mesh->normals) {
    const double len = n.norm();
    n = len > 0.0 ? Vec3(n / len) : Vec3::UnitZ();
  }
}

}  // namespace surfdeform
