// Flattened surfaces and animations' sheets, kept by content id: the first
// level in process (an LRU bounded by bytes, single flight: concurrent
// requests for one id share one flattening), the second level in Redis when
// the service has a shared tier (sheets only, encoded by sheet_codec.hpp,
// rebuilt and checked when read back; one replica flattens a new surface
// while the others wait on its lock, for a bounded time).
//
// The store flattens on a miss. Only that flattening takes a slot from
// admission when asked: a hit, or a wait on another request's flattening of
// the same surface, is never refused by the limit (checklist 27; the wait is
// bounded by that flattening's own time budget).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "base/status.hpp"
#include "engine/animation/animation.hpp"
#include "engine/flatten/flatten.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/surface/surface.hpp"
#include "proto/api.hpp"
#include "service/admission.hpp"
#include "service/model_store.hpp"
#include "service/request_clock.hpp"
#include "service/service_limits.hpp"
#include "service/shared_tier.hpp"
#include "service/sheet_codec.hpp"
#include "service/single_flight_cache.hpp"

namespace surfdeform {

// A flattened surface as the store holds it: immutable once built.
struct StoredSurface {
  std::string id;
  proto::SurfaceRequest request;
  std::unique_ptr<const Surface> surface;
  FlatSheet sheet;
  // The map of `surface` and `sheet` (their locator, and their continuation
  // past a seam), built once with the entry (KeepMap) and used by every
  // request on it; it refers to the two above, so the entry never moves.
  std::unique_ptr<const SheetMap> map;
  double flatten_ms = 0.0;
  size_t bytes = 0;
};

// An animation's sheets as the store holds them: immutable once built.
struct StoredAnimation {
  std::string id;
  proto::AnimationRequest request;
  AnimatedSheets sheets;
  double flatten_ms = 0.0;
  size_t bytes = 0;
};

// A digest of the sheet's points and layout (32 hex digits): sheets with
// one id may differ (a warm start from an edit ends within the solver's
// tolerance of a cold flattening), and answers are keyed by the sheet.
std::string SheetDigest(const FlatSheet& sheet);

// What the store's entries take in memory, estimated (for the LRU's budget).
size_t EstimateBytes(const StoredSurface& s);
// Builds the entry's map (StoredSurface::map) and sets its estimated bytes.
void KeepMap(StoredSurface* entry);
size_t EstimateBytes(const StoredAnimation& a);

// What a surface made for editing keeps for the next edit of it: the paths
// its distances followed, and how its sheet changed from the one it started
// from (empty for a cold start), which the next edit's solve starts along.
struct EditTrail {
  DistancePaths paths;
  SheetTrend trend;
  size_t bytes() const { return paths.bytes() + trend.bytes(); }
};

// What the trails of edited surfaces take at most (see
// SurfaceStore::Flattened): some 60 bytes a pair and 40 a sample, 1.3 MB for
// a 32 x 32 grid and 5 MB for 64 x 64, so a few dozen editors' latest
// surfaces.
inline constexpr size_t kEditPathsBytes = size_t{64} << 20;

// A flattening made for an edit (POST /v1/surfaces), which the next edit of
// the surface may start from.
struct EditStart {
  // Keep the distance paths this flattening follows, and how its sheet
  // changed from the one it started from, for the next edit.
  bool keep_paths = false;
  // The surface this one is an edit of, whose sheet it starts from (a warm
  // start), and whose kept paths, if any, it measures from; may be null.
  const StoredSurface* from = nullptr;
};

class SurfaceStore {
 public:
  // `engine_threads`: threads per flattening (0: one per core). `shared`:
  // the second level, or null.
  SurfaceStore(const ServiceLimits& limits, int engine_threads, std::shared_ptr<SharedTier> shared);
  SurfaceStore(const SurfaceStore&) = delete;
  SurfaceStore& operator=(const SurfaceStore&) = delete;

  // The flattened surface for `request`: from either level, or flattened now
  // (then written to the second level). *hit says it was not flattened here.
  // With `admission`, the flattening takes a slot from it first, and as many
  // threads as the slot allows.
  // `edit` says where a flattening here starts from (an edit's previous
  // surface, of the same grid), and whether its distance paths are kept,
  // apart from the entries, in an LRU of kEditPathsBytes (they are 20 times
  // the size of the sheet; an entry rebuilt from the second level has none).
  Result<std::shared_ptr<const StoredSurface>> Flattened(const proto::SurfaceRequest& request,
                                                         const RequestClock& clock, bool* hit,
                                                         Admission* admission = nullptr,
                                                         const EditStart& edit = {});

  // The surface with this id, from either level; kNotFound (field "id") for
  // an id of the wrong shape or one neither level holds.
  Result<std::shared_ptr<const StoredSurface>> Find(std::string_view id);

  // The sheets of an animation, from the first level or flattened now with
  // `threads` (the caller holds a slot). Animations are not shared.
  Result<std::shared_ptr<const StoredAnimation>> FlattenedAnimation(
      const proto::AnimationRequest& request, const RequestClock& clock, int threads, bool* hit);

  CacheStats surface_stats() const { return surfaces_.stats(); }
  CacheStats animation_stats() const { return animations_.stats(); }
  CacheStats edit_paths_stats() const { return edit_paths_.stats(); }
  SharedTierStats shared_tier_stats() const;  // enabled = false without one

  // Where surfaces of kind "mesh" find their meshes (by model id); until it
  // is set they fail (kInternal). Kept, not owned.
  void UseModels(ModelStore* models) { models_ = models; }

 private:
  // `spec` with its mesh found and flattened, for kind "mesh": the mesh
  // checked as a disk (limits.max_surface_mesh_vertices) and flattened with
  // `options`. nullopt for the other kinds, which need nothing.
  // With `shared` (a value of the second level), the mesh is checked but
  // not flattened again: its FlatMesh is assembled from the value's flat
  // vertices and the sheet's `quality`.
  Result<std::optional<SurfaceSpec>> ResolveMesh(const SurfaceSpec& spec,
                                                 const FlattenOptions& options,
                                                 const EncodedSheetParts* shared = nullptr,
                                                 const FlattenQuality& quality = {});
  // The animation with its keyframes of kind "mesh" resolved: each mesh
  // found by its model id, checked as a disk (MeshSpec::disk; one mesh
  // resolved once for all its keys), and the frames checked against the
  // memory budget. Others unchanged.
  Result<AnimationSpec> ResolveMeshKeys(const AnimationSpec& spec);
  class SharedLock;
  std::shared_ptr<const StoredSurface> FromShared(const std::string& id);
  Result<std::shared_ptr<const StoredSurface>> Rebuild(const std::string& id,
                                                       std::string_view value);
  std::shared_ptr<const StoredSurface> WaitForShared(const std::string& id,
                                                     const RequestClock& clock);
  Result<std::shared_ptr<const StoredSurface>> Flatten(const std::string& id,
                                                       const proto::SurfaceRequest& request,
                                                       const RequestClock& clock,
                                                       Admission* admission, const EditStart& edit);

  const ServiceLimits limits_;
  const int engine_threads_;
  const std::shared_ptr<SharedTier> shared_;  // may be null
  ModelStore* models_ = nullptr;
  SingleFlightCache<StoredSurface> surfaces_;
  SingleFlightCache<StoredAnimation> animations_;
  SingleFlightCache<EditTrail> edit_paths_;  // by surface id
};

}  // namespace surfdeform
