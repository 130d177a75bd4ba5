// A triangle mesh with per-vertex attributes, as the engine deforms it.
// Attribute arrays are either empty or hold one value per vertex; every
// attribute the input has is carried to the output.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "engine/common/geometry_types.hpp"

namespace surfdeform {

using Vec4 = Eigen::Vector4d;

// A run of triangles that share a material (a glTF primitive, an OBJ usemtl
// group). `material` indexes the importer's material list, -1 for none.
struct MeshGroup {
  std::string name;
  int material = -1;
  uint32_t first_triangle = 0;
  uint32_t triangle_count = 0;
  // The input's unit these triangles came from, for rigid "groups": the glTF
  // node, the OBJ g/o group (-1: none; the group is its own unit).
  int part = -1;
};

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;   // unit length
  std::vector<Vec4> tangents;  // xyz unit, w = +1 or -1 (bitangent sign), as glTF
  std::vector<Vec2> uv0;
  std::vector<Vec2> uv1;
  std::vector<Vec4> colors;  // RGBA
  // Written by the deformation when asked for (DeformOptions::distortion),
  // never read from a file: per vertex, (s1 - 1, s2 - 1) with s1 >= s2 the
  // singular values of the deformation's Jacobian along the sheet (see
  // engine/distortion.hpp). Exported as glTF's _DISTORTION and two PLY properties.
  std::vector<Vec2> distortion;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<MeshGroup> groups;  // cover the triangles in order; empty = one group

  size_t vertex_count() const { return positions.size(); }
};

// Checks the invariants above: attribute sizes, indices in range, groups
// covering the triangles. Returns a description of the first violation, or
// an empty string.
std::string CheckMesh(const Mesh& mesh);

// The index of the first vector in `values` with a component that is not
// finite or whose magnitude is 2^max_exponent or more, or -1 (a branch-free
// pass first, which the compiler vectorises: meshes are checked on every
// request).
template <typename V>
long long FirstBeyond(const std::vector<V>& values, int max_exponent) {
  static_assert(std::is_same_v<typename V::Scalar, double>, "the pass reads IEEE doubles");
  // A double is 2^max_exponent or more in magnitude (or not finite) when its
  // 11 biased exponent bits are at least 1023 + max_exponent: then adding
  // 2048 - (1023 + max_exponent) carries into bit 11. Integer operations
  // only, OR-ed.
  const uint64_t addend = static_cast<uint64_t>(2048 - (1023 + max_exponent));
  const double* x = values.empty() ? nullptr : values.data()->data();
  const size_t count = values.size() * static_cast<size_t>(V::SizeAtCompileTime);
  uint64_t carry = 0;
  for (size_t k = 0; k < count; ++k) {
    uint64_t bits;
    std::memcpy(&bits, x + k, sizeof bits);
    carry |= ((bits >> 52) & 0x7ff) + addend;
  }
  if ((carry & 0x800) == 0) return -1;
  const double bound = std::ldexp(1.0, max_exponent);
  for (size_t k = 0; k < values.size(); ++k) {
    if (!(values[k].array().abs() < bound).all()) return static_cast<long long>(k);
  }
  return -1;
}

// The first vector with a component that is not finite, or -1.
template <typename V>
long long FirstNonFinite(const std::vector<V>& values) {
  return FirstBeyond(values, 1024);  // 2^1024: the exponent of inf and NaN
}

// The first vector with a component that a float cannot hold (not finite,
// or 2^127 or more in magnitude, a margin under FLT_MAX), or -1: meshes are
// written in float32.
template <typename V>
long long FirstBeyondFloat(const std::vector<V>& values) {
  return FirstBeyond(values, 127);
}

// Sets `normals` to the area-weighted average of the adjacent face normals
// (+Z for a vertex with no non-degenerate face). A mesh that shares vertices
// across a crease gets smooth normals there: split such vertices first.
void ComputeVertexNormals(Mesh* mesh);

}  // namespace surfdeform
