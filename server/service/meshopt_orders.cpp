#include "service/meshopt_orders.hpp"

#include <xxhash.h>

#include "service/digest_hex.hpp"

namespace surfdeform {
namespace {

template <typename T>
void Feed(XXH3_state_t* state, const T& value) {
  XXH3_128bits_update(state, &value, sizeof value);
}

std::string TopologyKey(const Mesh& mesh) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset(state);
  Feed(state, mesh.positions.size());
  Feed(state, mesh.groups.size());
  for (const MeshGroup& g : mesh.groups) {
    Feed(state, g.first_triangle);
    Feed(state, g.triangle_count);
  }
  Feed(state, mesh.triangles.size());
  static_assert(sizeof(mesh.triangles[0]) == 3 * sizeof(uint32_t), "triangles are packed triples");
  XXH3_128bits_update(state, mesh.triangles.data(),
                      mesh.triangles.size() * sizeof(mesh.triangles[0]));
  const XXH128_hash_t digest = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  return DigestHex(digest);
}

}  // namespace

MeshoptOrders::MeshoptOrders()
    : orders_(kMeshoptOrderBytes, [](const MeshoptOrder& o) { return o.bytes(); }) {}

Result<std::shared_ptr<const MeshoptOrder>> MeshoptOrders::For(const Mesh& mesh) {
  bool hit = false;
  return orders_.GetOrCompute(
      TopologyKey(mesh),
      [&mesh]() -> Result<std::shared_ptr<const MeshoptOrder>> {
        SURFDEFORM_ASSIGN_OR_RETURN(MeshoptOrder order, ComputeMeshoptOrder(mesh));
        return std::make_shared<const MeshoptOrder>(std::move(order));
      },
      &hit);
}

}  // namespace surfdeform
