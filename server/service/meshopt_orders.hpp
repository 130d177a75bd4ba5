// The vertex orders of meshopt answers (ComputeMeshoptOrder, the costly
// part of encoding one: ~0.5 us a triangle against ~0.14 us a vertex for
// the rest), kept per topology: a model deformed again with another
// placement or surface has the same triangles, and so the same order.
// Keyed by a digest of the vertex count, groups and triangles; an LRU of
// kMeshoptOrderBytes, single flight.
#pragma once

#include <memory>

#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "meshio/mesh_export.hpp"
#include "service/single_flight_cache.hpp"

namespace surfdeform {

// ~6 bytes a triangle: the bunny's takes 1 MB, a 1.2M-triangle scan's 17 MB.
inline constexpr size_t kMeshoptOrderBytes = size_t{64} << 20;

class MeshoptOrders {
 public:
  MeshoptOrders();

  // The order for this mesh: kept, or computed now and kept.
  Result<std::shared_ptr<const MeshoptOrder>> For(const Mesh& mesh);

  CacheStats stats() const { return orders_.stats(); }

 private:
  SingleFlightCache<MeshoptOrder> orders_;
};

}  // namespace surfdeform
