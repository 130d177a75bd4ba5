#include "service/surface_store.hpp"

#include <xxhash.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <map>
#include <optional>
#include <thread>
#include <type_traits>
#include <variant>

#include "engine/common/disk_mesh.hpp"
#include "engine/common/elapsed.hpp"
#include "engine/flatten/mesh_flatten.hpp"
#include "engine/surface/surface_fields.hpp"
#include "engine/surface/surface_spec.hpp"
#include "json/bounded_json.hpp"
#include "proto/content_hash.hpp"
#include "proto/json_object.hpp"
#include "service/digest_hex.hpp"
#include "service/engine_options.hpp"
#include "service/limit_checks.hpp"
#include "service/memory_budget.hpp"
#include "service/sheet_codec.hpp"

namespace surfdeform {

using Clock = std::chrono::steady_clock;

size_t EstimateBytes(const StoredAnimation& a) {
  size_t samples = 0;
  for (const FlatSheet& s : a.sheets.sheets) samples += s.points.size();
  // Samples: position, normal, flat position; each frame's surface about as
  // much as a key's spec (a Bezier's control points, a grid's points).
  // A frame of a mesh's animation keeps its flat mesh and triangle index.
  size_t mesh_vertices = 0;
  for (const auto& surface : a.sheets.surfaces) {
    if (const FlatMesh* m = surface->flat_mesh()) mesh_vertices += m->flat.size();
  }
  return sizeof(StoredAnimation) + samples * (24 + 24 + 16) + a.sheets.surfaces.size() * 4096 +
         static_cast<size_t>(kMeshAnimationBytesPerFrameVertex *
                             static_cast<double>(mesh_vertices)) +
         1024;
}

std::string SheetDigest(const FlatSheet& sheet) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset(state);
  const int layout[2] = {sheet.nu, sheet.nv};
  XXH3_128bits_update(state, layout, sizeof layout);
  XXH3_128bits_update(state, sheet.flat.data(), sheet.flat.size() * sizeof(Vec2));
  XXH3_128bits_update(state, sheet.points.data(), sheet.points.size() * sizeof(Vec3));
  XXH3_128bits_update(state, sheet.frame_linear.data(), 4 * sizeof(double));
  XXH3_128bits_update(state, sheet.frame_offset.data(), 2 * sizeof(double));
  XXH3_128bits_update(state, sheet.period_u.data(), 2 * sizeof(double));
  XXH3_128bits_update(state, sheet.period_v.data(), 2 * sizeof(double));
  XXH3_128bits_update(state, sheet.method.data(), sheet.method.size());
  const XXH128_hash_t digest = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  return DigestHex(digest);
}

void KeepMap(StoredSurface* entry) {
  entry->map = std::make_unique<const SheetMap>(*entry->surface, entry->sheet);
  entry->bytes = EstimateBytes(*entry);
}

size_t EstimateBytes(const StoredSurface& s) {
  const size_t samples = s.sheet.points.size();
  // The description: 8 B a number (a grid keeps 4 times that: its
  // interpolation's coefficients).
  const bool grid = std::holds_alternative<GridSpec>(s.request.surface);
  size_t spec = CountNumbers(s.request.surface) * 8 * (grid ? 4 : 1);
  // Samples: position, normal and flat position; the surface keeps about as
  // much again as its spec (copies, derived coefficients).
  // The kept map: its locator (about 64 B a sample), and past a seam the
  // continued sheet's samples and locator beside the given sheet's locator.
  size_t map = 0;
  if (s.map != nullptr) {
    const size_t mapped = s.map->sheet().flat.size();
    map = 64 * mapped +
          (s.map->periodic_u() || s.map->periodic_v() ? mapped * (24 + 24 + 16) + 64 * samples : 0);
  }
  // A mesh surface's flattening: per vertex its position, flat position and
  // normal; per triangle its corners, neighbours and index entries.
  if (s.surface != nullptr) {
    if (const FlatMesh* m = s.surface->flat_mesh()) {
      spec += m->flat.size() * (24 + 16 + 24) + m->mesh.triangles.size() * (12 + 12 + 56);
    }
  }
  return sizeof(StoredSurface) + samples * (24 + 24 + 16) + 2 * spec + map + 1024;
}

// Releases a cross-replica flattening lock however the flattening ends.
class SurfaceStore::SharedLock {
 public:
  SharedLock(SharedTier* tier, std::string key, std::string token)
      : tier_(tier), key_(std::move(key)), token_(std::move(token)) {}
  SharedLock(const SharedLock&) = delete;
  SharedLock& operator=(const SharedLock&) = delete;
  ~SharedLock() { tier_->Unlock(key_, token_); }

 private:
  SharedTier* tier_;
  std::string key_, token_;
};

SurfaceStore::SurfaceStore(const ServiceLimits& limits, int engine_threads,
                           std::shared_ptr<SharedTier> shared)
    : limits_(limits),
      engine_threads_(engine_threads),
      shared_(std::move(shared)),
      surfaces_(limits.cache_bytes, [](const StoredSurface& s) { return s.bytes; }),
      animations_(limits.cache_bytes, [](const StoredAnimation& a) { return a.bytes; }),
      edit_paths_(kEditPathsBytes, [](const EditTrail& t) { return t.bytes(); }) {}

SharedTierStats SurfaceStore::shared_tier_stats() const {
  return shared_ != nullptr ? shared_->stats() : SharedTierStats{};
}

Result<std::shared_ptr<const StoredSurface>> SurfaceStore::Flattened(
    const proto::SurfaceRequest& request, const RequestClock& clock, bool* hit,
    Admission* admission, const EditStart& edit) {
  SURFDEFORM_RETURN_IF_ERROR(CheckGrid(limits_, request.sampling, request.flatten));
  const std::string id = proto::SurfaceId(request);
  bool from_shared = false;  // computed here, but read from the second level
  auto result = surfaces_.GetOrCompute(
      id,
      [&]() -> Result<std::shared_ptr<const StoredSurface>> {
        // The second level first; then, holding its lock (or when another
        // replica holds it but never finishes), flatten here.
        std::optional<SharedLock> lock;
        if (shared_ != nullptr) {
          if (auto e = FromShared(id)) {
            from_shared = true;
            return e;
          }
          std::string token;
          switch (shared_->TryLock(SheetLockKey(id), &token)) {
            case SharedTier::Lock::kAcquired:
              lock.emplace(shared_.get(), SheetLockKey(id), std::move(token));
              break;
            case SharedTier::Lock::kHeldElsewhere:
              if (auto e = WaitForShared(id, clock)) {
                from_shared = true;
                return e;
              }
              break;
            case SharedTier::Lock::kUnavailable:
              break;
          }
        }
        return Flatten(id, request, clock, admission, edit);
      },
      hit);
  if (from_shared) *hit = true;
  return result;
}

Result<std::optional<SurfaceSpec>> SurfaceStore::ResolveMesh(const SurfaceSpec& spec,
                                                             const FlattenOptions& options,
                                                             const EncodedSheetParts* shared,
                                                             const FlattenQuality& quality) {
  const auto* given = std::get_if<MeshSpec>(&spec);
  if (given == nullptr) return std::optional<SurfaceSpec>();
  if (models_ == nullptr) {
    return Status(ErrorCode::kInternal, "this store has no models for mesh surfaces");
  }
  auto model = models_->Find(given->model_id);
  if (!model.ok()) return model.status().WithFieldPrefix("surface");
  const Mesh& mesh = (*model)->imported.mesh;
  DiskMeshOptions disk_options;
  disk_options.max_vertices = limits_.max_surface_mesh_vertices;
  auto disk = MakeDiskMesh(mesh.positions, mesh.triangles, disk_options);
  if (!disk.ok()) return disk.status().WithFieldPrefix("surface");
  const size_t vertices = disk->positions.size();
  FlattenOptions bounded = options;
  if (shared == nullptr) SURFDEFORM_RETURN_IF_ERROR(CheckSurfaceMesh(limits_, vertices));
  bounded.max_mesh_pairs = MaxSurfaceMeshPairs(limits_, vertices);
  auto made = shared == nullptr ? FlattenMesh(std::move(*disk), bounded)
                                : AssembleFlatMesh(std::move(*disk), shared->mesh_flat, quality);
  if (!made.ok()) return SurfaceMeshPairsError(limits_, vertices, made.status());
  if (shared != nullptr) {
    made->pairs = shared->mesh_pairs;
    made->dropped_pairs = shared->mesh_dropped_pairs;
  }
  MeshSpec out = *given;
  out.flattened = std::make_shared<const FlatMesh>(std::move(*made));
  return std::optional<SurfaceSpec>(std::move(out));
}

Result<AnimationSpec> SurfaceStore::ResolveMeshKeys(const AnimationSpec& spec) {
  AnimationSpec out = spec;
  std::map<std::string, std::shared_ptr<const DiskMesh>> resolved;
  for (size_t k = 0; k < out.keyframes.size(); ++k) {
    auto* key = std::get_if<MeshSpec>(&out.keyframes[k].surface);
    if (key == nullptr) continue;
    std::shared_ptr<const DiskMesh>& disk = resolved[key->model_id];
    if (disk == nullptr) {
      const std::string field = "animation.keyframes[" + std::to_string(k) + "].surface";
      if (models_ == nullptr) {
        return Status(ErrorCode::kInternal, "this store has no models for mesh surfaces");
      }
      auto model = models_->Find(key->model_id);
      if (!model.ok()) return model.status().WithFieldPrefix(field);
      const Mesh& mesh = (*model)->imported.mesh;
      DiskMeshOptions disk_options;
      disk_options.max_vertices = limits_.max_surface_mesh_vertices;
      auto made = MakeDiskMesh(mesh.positions, mesh.triangles, disk_options);
      if (!made.ok()) return made.status().WithFieldPrefix(field);
      disk = std::make_shared<const DiskMesh>(std::move(*made));
    }
    key->disk = disk;
  }
  if (const auto* m = std::get_if<MeshSpec>(&out.keyframes[0].surface)) {
    // What the frames and keys will take, before the work that grows with
    // them; then the meshes' topology, now that they are known.
    SURFDEFORM_RETURN_IF_ERROR(
        CheckMeshFrames(limits_, out.frames, out.keyframes.size(), m->disk->positions.size()));
    SURFDEFORM_RETURN_IF_ERROR(
        ValidateAnimation(out, std::numeric_limits<int>::max()).WithFieldPrefix("animation"));
  }
  return out;
}

Result<std::shared_ptr<const StoredSurface>> SurfaceStore::Flatten(
    const std::string& id, const proto::SurfaceRequest& request, const RequestClock& clock,
    Admission* admission, const EditStart& edit) {
  std::optional<Admission::Ticket> ticket;
  if (admission != nullptr) {
    SURFDEFORM_ASSIGN_OR_RETURN(auto t, admission->Enter(clock.remaining_ms()));
    ticket.emplace(std::move(t));
  }
  const auto t0 = Clock::now();
  FlattenOptions flatten =
      FlattenFor(request.flatten, ticket ? ThreadsFor(*ticket, engine_threads_) : engine_threads_,
                 clock, limits_.flatten_time_budget_ms);
  auto resolved = ResolveMesh(request.surface, flatten);
  if (!resolved.ok()) {
    const Status& s = resolved.status();
    return s.field().empty() ? Status(s.code(), s.message(), "surface") : s;
  }
  auto surface = MakeSurface(*resolved ? **resolved : request.surface);
  if (!surface.ok()) return surface.status().WithFieldPrefix("surface");
  Flattener flattener(flatten);
  const FlatSheet* warm = edit.from != nullptr ? &edit.from->sheet : nullptr;
  const bool fits =
      warm != nullptr && warm->nu == request.sampling.nu && warm->nv == request.sampling.nv;
  const std::shared_ptr<const EditTrail> warm_trail =
      fits ? edit_paths_.Find(edit.from->id) : nullptr;
  // What this flattening leaves for the next edit: kept apart from the
  // entry (a sheet's 20 times over).
  auto trail = edit.keep_paths ? std::make_shared<EditTrail>() : nullptr;
  auto sheet = flattener.Flatten(
      **surface, request.sampling, fits ? warm : nullptr,
      warm_trail != nullptr ? &warm_trail->paths : nullptr, trail ? &trail->paths : nullptr,
      warm_trail != nullptr && !warm_trail->trend.empty() ? &warm_trail->trend : nullptr);
  if (!sheet.ok()) {
    const Status& s = sheet.status();
    // Sampling errors name a sample of the surface.
    return s.field().empty() ? Status(s.code(), s.message(), "surface") : s;
  }
  if (trail != nullptr && trail->paths.nu > 0) {  // none: a mesh
    if (fits) trail->trend = TrendBetween(*warm, *sheet);
    edit_paths_.Put(id, std::move(trail));
  }
  auto entry = std::make_shared<StoredSurface>();
  entry->id = id;
  entry->request = request;
  entry->surface = std::move(*surface);
  entry->sheet = std::move(*sheet);
  entry->flatten_ms = MsSince(t0);
  KeepMap(entry.get());
  if (shared_ != nullptr) {
    EncodedSheetParts parts{proto::CanonicalJson(request).dump(), entry->flatten_ms, {}, 0, 0};
    if (const FlatMesh* m = entry->surface->flat_mesh()) {
      // A mesh surface's flat vertices too: another replica needs them, with
      // the mesh (which it finds by its model id), not to flatten again.
      parts.mesh_flat = m->flat;
      parts.mesh_pairs = m->pairs;
      parts.mesh_dropped_pairs = m->dropped_pairs;
    }
    shared_->Put(SheetKey(id), EncodeSheet(entry->sheet, parts));
  }
  return std::shared_ptr<const StoredSurface>(std::move(entry));
}

// Surface `id` from the second level, checked and rebuilt; nullptr for a
// miss, an unreachable tier, or a value that fails any check (counted).
std::shared_ptr<const StoredSurface> SurfaceStore::FromShared(const std::string& id) {
  std::string value;
  if (shared_->Get(SheetKey(id), &value) != SharedTier::Lookup::kHit) return nullptr;
  auto entry = Rebuild(id, value);
  if (!entry.ok()) {
    shared_->CountCorrupt();
    return nullptr;
  }
  return *entry;
}

Result<std::shared_ptr<const StoredSurface>> SurfaceStore::Rebuild(const std::string& id,
                                                                   std::string_view value) {
  SURFDEFORM_ASSIGN_OR_RETURN(
      auto decoded, DecodeSheet(value, limits_.max_grid_side, limits_.max_surface_mesh_vertices));
  SURFDEFORM_ASSIGN_OR_RETURN(auto parsed, ParseBoundedJson(decoded.parts.canonical_request,
                                                            JsonLimitsOf(limits_), "shared_tier"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto request, proto::ParseSurfaceRequest(parsed));
  if (proto::SurfaceId(request) != id || request.sampling.nu != decoded.sheet.nu ||
      request.sampling.nv != decoded.sheet.nv) {
    return Status(ErrorCode::kMalformed, "the shared sheet answers another request", "shared_tier");
  }
  SURFDEFORM_RETURN_IF_ERROR(CheckGrid(limits_, request.sampling, request.flatten));
  // A mesh surface: its mesh by its model id (either level of the models),
  // laid out as the value says.
  const bool mesh = std::holds_alternative<MeshSpec>(request.surface);
  if (mesh != !decoded.parts.mesh_flat.empty()) {
    return Status(ErrorCode::kMalformed, "the shared sheet's mesh does not match its surface",
                  "shared_tier");
  }
  SURFDEFORM_ASSIGN_OR_RETURN(
      auto resolved, ResolveMesh(request.surface, WithRunDefaults<FlattenOptions>(request.flatten),
                                 &decoded.parts, decoded.sheet.quality));
  SURFDEFORM_ASSIGN_OR_RETURN(auto surface, MakeSurface(resolved ? *resolved : request.surface));
  auto entry = std::make_shared<StoredSurface>();
  entry->id = id;
  entry->request = std::move(request);
  entry->surface = std::move(surface);
  entry->sheet = std::move(decoded.sheet);
  entry->flatten_ms = decoded.parts.flatten_ms;
  KeepMap(entry.get());
  return std::shared_ptr<const StoredSurface>(std::move(entry));
}

// Another replica holds the lock on `id`: its value, once the lock is
// released, or nullptr after the tier's wait bound (or half of what is left
// of this request's budget, whichever is less); then this replica flattens.
std::shared_ptr<const StoredSurface> SurfaceStore::WaitForShared(const std::string& id,
                                                                 const RequestClock& clock) {
  const SharedTierOptions& o = shared_->options();
  const auto t0 = Clock::now();
  const double bound = std::min(o.wait_ms, clock.remaining_ms() / 2);
  const auto poll = std::chrono::duration<double, std::milli>(o.poll_ms);
  while (MsSince(t0) < bound) {
    std::this_thread::sleep_for(poll);
    if (shared_->Exists(SheetLockKey(id)) && MsSince(t0) < bound) continue;
    auto e = FromShared(id);
    shared_->CountLockWait(e != nullptr);
    return e;
  }
  shared_->CountLockWait(false);
  return FromShared(id);
}

Result<std::shared_ptr<const StoredSurface>> SurfaceStore::Find(std::string_view id) {
  if (!proto::IsSurfaceIdShaped(id)) {
    return Status(ErrorCode::kNotFound,
                  "no surface has this id (ids are 32 hex digits from POST /v1/surfaces)", "id");
  }
  std::shared_ptr<const StoredSurface> found;
  if (shared_ == nullptr) {
    found = surfaces_.Find(std::string(id));
  } else {  // a miss here reads the second level (once for concurrent callers)
    bool hit = false;
    auto fetched = surfaces_.GetOrCompute(
        std::string(id),
        [&]() -> Result<std::shared_ptr<const StoredSurface>> {
          if (auto e = FromShared(std::string(id))) return e;
          return Status(ErrorCode::kNotFound, "not in the shared tier");
        },
        &hit);
    if (fetched.ok()) found = *fetched;
  }
  if (found == nullptr) {
    return Status(ErrorCode::kNotFound,
                  "no flattened surface with this id is cached here (it may have been evicted): "
                  "POST its description to /v1/surfaces again, or send it inline",
                  "id");
  }
  return found;
}

Result<std::shared_ptr<const StoredAnimation>> SurfaceStore::FlattenedAnimation(
    const proto::AnimationRequest& request, const RequestClock& clock, int threads, bool* hit) {
  SURFDEFORM_RETURN_IF_ERROR(CheckFrames(limits_, request));
  const std::string id = proto::AnimationId(request);
  return animations_.GetOrCompute(
      id,
      [&]() -> Result<std::shared_ptr<const StoredAnimation>> {
        const auto t0 = Clock::now();
        FlattenOptions flatten =
            FlattenFor(request.flatten, threads, clock, limits_.flatten_time_budget_ms);
        SURFDEFORM_ASSIGN_OR_RETURN(const AnimationSpec spec, ResolveMeshKeys(request.animation));
        size_t mesh_vertices = 0;
        if (const auto* m = std::get_if<MeshSpec>(&spec.keyframes[0].surface)) {
          mesh_vertices = m->disk->positions.size();
          flatten.max_mesh_pairs = MaxSurfaceMeshPairs(limits_, mesh_vertices);
        }
        auto sheets = FlattenAnimation(spec, request.sampling, flatten);
        if (!sheets.ok() && mesh_vertices > 0) {
          sheets = SurfaceMeshPairsError(limits_, mesh_vertices, sheets.status());
        }
        if (!sheets.ok()) {
          const Status& st = sheets.status();
          if (st.code() == ErrorCode::kDeadlineExceeded) return st;
          // The frame's surface is at fault: name the animation.
          return Status(st.code(), st.message(),
                        st.field().empty() ? std::string("animation") : st.field());
        }
        auto entry = std::make_shared<StoredAnimation>();
        entry->id = id;
        entry->request = request;
        entry->sheets = std::move(*sheets);
        entry->flatten_ms = MsSince(t0);
        entry->bytes = EstimateBytes(*entry);
        return std::shared_ptr<const StoredAnimation>(std::move(entry));
      },
      hit);
}

}  // namespace surfdeform
