// Internal to the mesh flattening (mesh_flatten.hpp): the conformal start,
// the vertex pairs within a number of rings, and their distances along a
// chart's straight segments. Not part of the engine's public surface.
#pragma once

#include <chrono>
#include <optional>
#include <vector>

#include "base/status.hpp"
#include "engine/common/disk_mesh.hpp"
#include "engine/common/elapsed.hpp"
#include "engine/common/geometry_types.hpp"
#include "engine/distance/surface_distance.hpp"

namespace surfdeform::internal {

// Vertex to neighbours and vertex to triangles, compressed rows.
struct MeshAdjacency {
  std::vector<int>
      vertex_start;  // neighbours of v: vertices[vertex_start[v] .. vertex_start[v + 1])
  std::vector<int> vertices;
  std::vector<int> triangle_start;  // likewise triangles of v
  std::vector<int> triangles;
};
MeshAdjacency Adjacency(const DiskMesh& mesh);

// The least-squares conformal map of the mesh (its boundary free), with the
// two boundary vertices farthest apart pinned at their distance in space
// along +X. kNotConverged when the factorisation fails.
Result<std::vector<Vec2>> ConformalChart(const DiskMesh& mesh);

// The pairs i < j within `rings` rings (ring = the fewest mesh edges between
// them), ordered by i then j; d unset. On `threads` threads; the order does
// not depend on them. With `max_pairs` > 0, std::nullopt as soon as there
// are more (the listing stops there: a vertex that joins very many
// triangles would otherwise make its neighbourhoods quadratic).
std::optional<std::vector<GridEdge>> RingPairs(const MeshAdjacency& adjacency, int rings,
                                               int threads, size_t max_pairs = 0);

// Sets each pair's d to the mesh length of the straight segment between its
// vertices in `chart` (a layout of the mesh's vertices without folds; ring-1
// pairs: the edge's length). Pairs whose segment leaves the mesh keep their
// d if it is positive and get d = -1 otherwise. Deterministic on any
// number of threads. False when it stopped at `deadline` (the pairs then
// half measured).
bool MeasureAlongChart(const DiskMesh& mesh, const MeshAdjacency& adjacency,
                       const std::vector<Vec2>& chart, int threads, std::vector<GridEdge>* pairs,
                       Deadline deadline = Deadline());

}  // namespace surfdeform::internal
