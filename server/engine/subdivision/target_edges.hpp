// The edges of a surface given as a mesh, on the sheet (the paper's section
// 3): the map from the sheet to such a surface is flat on each of its
// triangles and bends only across its edges, so its edges and vertices play
// the part of the paper's grid lines and grid nodes. The subdivision's edge
// points are where a model's edge crosses a target edge, its face points the
// target vertices inside a model's face, and its chords the pieces of target
// edges inside a face.
//
// A mesh surface's sheet holds its flat mesh (MeshSurface's exact
// unrolling) in the sheet's frame (FlatSheet::frame_linear and
// frame_offset), where the index keeps its vertices. Crossings
// use GridCrossing with the target edge's index as `u_line` and the fraction
// along it (from its first vertex) as `u_along`; vertices inside a face use
// GridNodeInside with the target vertex's index as `i` and j = -1.
#pragma once

#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "engine/common/geometry_types.hpp"
#include "engine/common/uniform_buckets.hpp"
#include "engine/flatten/mesh_flatten.hpp"
#include "engine/subdivision/grid_points.hpp"

namespace surfdeform::subdivision {

class TargetEdges {
 public:
  // `mesh` flattened, put on the sheet by p -> linear p + offset.
  TargetEdges(const FlatMesh& mesh, const Eigen::Matrix2d& linear, const Vec2& offset);

  struct Edge {
    std::array<int, 2> v;  // its vertices, v[0] < v[1]
    // How much the map bends across it: the jump of its derivative across the
    // edge (the two triangles' derivatives along the flat perpendicular of
    // the edge; dimensionless, 0 on the boundary).
    double kink = 0.0;
    // The same for the normal field (vertex normals interpolated), per unit
    // of height: a point at height h above the edge kinks by at most
    // kink + |h| normal_kink.
    double normal_kink = 0.0;
    double length = 0.0;  // on the sheet
    double KinkAt(double h) const { return kink + std::abs(h) * normal_kink; }
  };

  // The target edges that segment a-b crosses in its interior, by
  // increasing t (crossings closer than 1e-7 of the segment's length to its
  // ends, and segments along an edge, are left out; where it passes through
  // a target vertex, one crossing stands for the edges there), and in
  // *min_length the shortest of them (infinity for none). `scratch` avoids
  // allocations across calls.
  void Crossings(const Vec2& a, const Vec2& b, std::vector<GridCrossing>* out, double* min_length,
                 std::vector<int>* scratch) const;
  // The target vertices strictly inside triangle a, b, c (either
  // orientation, at least 1e-7 of its size from its sides), by index.
  void VerticesInside(const Vec2& a, const Vec2& b, const Vec2& c,
                      std::vector<GridNodeInside>* out) const;

  const std::vector<Edge>& edges() const { return edges_; }
  // The edges that end at vertex v.
  std::span<const int> EdgesAt(int v) const {
    return {incident_.data() + incident_start_[v],
            static_cast<size_t>(incident_start_[v + 1] - incident_start_[v])};
  }
  // The largest kink at height h of the edges within `box` on the sheet.
  double MaxKinkIn(const Eigen::AlignedBox2d& box, double h) const;

 private:
  // The buckets segment a-b passes through (and both beside a corner it
  // passes): a long segment visits O(its length) buckets, not its box's.
  template <typename Visit>
  void ForBucketsAlong(const Vec2& a, const Vec2& b, Visit&& visit) const;

  std::vector<Vec2> flat_;  // the vertices on the sheet
  std::vector<Edge> edges_;
  std::vector<int> incident_start_, incident_;
  UniformBuckets grid_;
  std::vector<int> edge_start_, edge_ids_;      // buckets of edges, compressed rows
  std::vector<int> vertex_start_, vertex_ids_;  // buckets of vertices
};

}  // namespace surfdeform::subdivision
