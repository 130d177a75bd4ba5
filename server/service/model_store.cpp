#include "service/model_store.hpp"

#include "proto/api.hpp"
#include "service/limit_checks.hpp"
#include "service/model_codec.hpp"

namespace surfdeform {
namespace {

template <typename V>
size_t BytesOf(const std::vector<V>& v) {
  return v.size() * sizeof(V);
}

}  // namespace

size_t EstimateBytes(const StoredModel& m) {
  const Mesh& mesh = m.imported.mesh;
  return sizeof(StoredModel) + BytesOf(mesh.positions) + BytesOf(mesh.normals) +
         BytesOf(mesh.tangents) + BytesOf(mesh.uv0) + BytesOf(mesh.uv1) + BytesOf(mesh.colors) +
         BytesOf(mesh.triangles) + BytesOf(mesh.groups) + m.file_bytes + 1024;
}

ModelStore::ModelStore(const ServiceLimits& limits, std::shared_ptr<SharedTier> shared)
    : limits_(limits),
      shared_(std::move(shared)),
      models_(limits.model_cache_bytes, [](const StoredModel& m) { return m.bytes; }) {}

Result<std::shared_ptr<const StoredModel>> ModelStore::Import(const std::string& id,
                                                              std::string_view file) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto imported, ImportMesh(file, ImportLimitsOf(limits_)));
  auto entry = std::make_shared<StoredModel>();
  entry->id = id;
  entry->imported = std::move(imported);
  entry->file_bytes = file.size();
  entry->bytes = EstimateBytes(*entry);
  return std::shared_ptr<const StoredModel>(std::move(entry));
}

Result<std::shared_ptr<const StoredModel>> ModelStore::Put(const std::string& id,
                                                           std::string_view file, bool* known) {
  bool in_shared = false;
  auto result = models_.GetOrCompute(
      id,
      [&]() -> Result<std::shared_ptr<const StoredModel>> {
        // The upload's own bytes are imported either way; the second level
        // is written only when it does not have them yet.
        SURFDEFORM_ASSIGN_OR_RETURN(auto entry, Import(id, file));
        if (shared_ != nullptr) {
          in_shared = shared_->Exists(ModelKey(id));
          if (!in_shared) shared_->Put(ModelKey(id), EncodeModel(file));
        }
        return entry;
      },
      known);
  if (in_shared) *known = true;
  return result;
}

Result<std::shared_ptr<const StoredModel>> ModelStore::Find(std::string_view id) {
  const auto unknown = [] {
    return Status(ErrorCode::kUnknownModel,
                  "no uploaded model has this id here (never uploaded, or evicted): POST the "
                  "mesh to /v1/models again, or send it in the request's body",
                  "model_id");
  };
  if (!proto::IsSurfaceIdShaped(id)) return unknown();
  std::shared_ptr<const StoredModel> found;
  if (shared_ == nullptr) {
    found = models_.Find(std::string(id));
  } else {  // a miss here reads the second level (once for concurrent callers)
    bool hit = false;
    const std::string key(id);
    auto fetched = models_.GetOrCompute(
        key,
        [&]() -> Result<std::shared_ptr<const StoredModel>> {
          std::string value;
          if (shared_->Get(ModelKey(key), &value) != SharedTier::Lookup::kHit) return unknown();
          auto file = DecodeModel(value, key, limits_.max_body_bytes);
          if (!file.ok()) {
            shared_->CountCorrupt();
            return unknown();
          }
          return Import(key, *file);
        },
        &hit);
    if (fetched.ok()) found = *fetched;
  }
  if (found == nullptr) return unknown();
  return found;
}

}  // namespace surfdeform
