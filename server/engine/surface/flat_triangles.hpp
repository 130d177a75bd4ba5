// A spatial index over a flattened triangle mesh (a mesh surface's sheet):
// which triangle holds a flat point, and the nearest point of the boundary.
// Uniform buckets of about one triangle each; O(1) per query on meshes
// without extreme size variation.
#pragma once

#include <array>
#include <vector>

#include "engine/common/geometry_types.hpp"
#include "engine/common/uniform_buckets.hpp"

namespace surfdeform {

class FlatTriangles {
 public:
  // Keeps no references. `boundary` is the boundary loop (vertex indices, in
  // order); boundary_triangles[k] is the triangle on edge boundary[k] ->
  // boundary[k + 1].
  FlatTriangles(const std::vector<Vec2>& flat, const std::vector<std::array<int, 3>>& triangles,
                const std::vector<int>& boundary, const std::vector<int>& boundary_triangles);

  // The triangle that holds `p` (its barycentric coordinates to `bary`), or -1.
  int Locate(const Vec2& p, Vec3* bary) const;

  struct Nearest {
    Vec2 point = Vec2::Zero();  // on the boundary
    double distance = 0.0;
    int triangle = -1;  // the triangle on that boundary edge
  };
  // The boundary point nearest `p`.
  Nearest NearestOnBoundary(const Vec2& p) const;

  // The barycentric coordinates of `p` in triangle f (any p: extrapolated).
  Vec3 Barycentric(int f, const Vec2& p) const;

  const Eigen::AlignedBox2d& bounds() const { return grid_.bounds(); }

 private:
  std::vector<Vec2> origin_;              // corner 0 of each triangle
  std::vector<Eigen::Matrix2d> inverse_;  // (corner 1 - 0, corner 2 - 0)^-1
  std::vector<std::array<Vec2, 2>> segments_;
  std::vector<int> segment_triangle_;
  UniformBuckets grid_;
  std::vector<int> triangle_start_, triangle_ids_;  // buckets, compressed rows
  std::vector<int> segment_start_, segment_ids_;
};

}  // namespace surfdeform
