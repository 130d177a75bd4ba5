// Uploaded models (POST /v1/models), kept by content id so that a client
// sends a mesh once and deforms it many times by `model_id`: the first level
// in process (an LRU bounded by its own byte budget, single flight), the
// second level in Redis when the service has a shared tier (the file's
// bytes, model_codec.hpp, imported again when read back), as for surfaces.
//
// A model is kept imported: a deformation by id copies the imported mesh
// and does exactly what it would with the same bytes in its body, so the
// result is byte-identical.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "base/status.hpp"
#include "meshio/mesh_import.hpp"
#include "service/service_limits.hpp"
#include "service/shared_tier.hpp"
#include "service/single_flight_cache.hpp"

namespace surfdeform {

// A model as the store holds it: immutable once built.
struct StoredModel {
  std::string id;  // proto::ModelId of the file's bytes
  ImportedMesh imported;
  size_t file_bytes = 0;
  size_t bytes = 0;  // memory, estimated (the LRU's budget)
};

// The imported mesh's arrays, plus the file's size (which bounds what a
// glTF's materials and images keep).
size_t EstimateBytes(const StoredModel& m);

class ModelStore {
 public:
  // The first level holds up to limits.model_cache_bytes; `shared`: the
  // second level, or null.
  ModelStore(const ServiceLimits& limits, std::shared_ptr<SharedTier> shared);
  ModelStore(const ModelStore&) = delete;
  ModelStore& operator=(const ModelStore&) = delete;

  // The model in `file` (a mesh file's bytes, within the service's import
  // limits), whose id is `id` (proto::ModelId(file): the caller has it
  // already, to check a routing header against, and SHA-256 of a large file
  // is not free), imported now unless the first level holds it, and written
  // to the second level unless that holds it. *known says either level held
  // it (the upload was not needed). Import errors as ImportMesh gives them.
  Result<std::shared_ptr<const StoredModel>> Put(const std::string& id, std::string_view file,
                                                 bool* known);

  // The model with this id, from either level; kUnknownModel (field
  // "model_id") for one neither holds.
  Result<std::shared_ptr<const StoredModel>> Find(std::string_view id);

  CacheStats stats() const { return models_.stats(); }

 private:
  Result<std::shared_ptr<const StoredModel>> Import(const std::string& id, std::string_view file);

  const ServiceLimits limits_;
  const std::shared_ptr<SharedTier> shared_;  // may be null
  SingleFlightCache<StoredModel> models_;
};

}  // namespace surfdeform
