// Placements of models that come back, and where their vertices lie on the
// sheet. The placement (with fit: a convex hull of the footprint and a
// bisection of the scale against the sheet's boundary) depends only on the
// model's positions, the sheet and the placement options, and costs ~0.6 ms
// of a bunny request's CPU; so does the footprint (engine/sheet_footprint.hpp:
// each vertex's cell and place in it, ~1.5 ms of the bunny's map). Load tests
// send one model again and again; a viewer sends the same model while its
// user tries other subdivisions, formats or distortion maps. The memo keys
// both by a digest of all three and keeps the most recent ones: placements
// by count, footprints (24 bytes a vertex) within a byte budget.
// An entry also keeps the verdict of the last adaptive subdivision that added
// nothing to its model (the bunny on a gentle surface: ~2.5 ms of screening
// its faces), keyed by the subdivision's options and the model's triangles:
// the same request again maps the model as it is.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/common/geometry_types.hpp"
#include "engine/deform/deform.hpp"
#include "engine/placement/placement.hpp"
#include "engine/sheet/sheet_footprint.hpp"
#include "engine/subdivision/subdivide.hpp"
#include "service/placement_memo_stats.hpp"

namespace surfdeform {

class PlacementMemo {
 public:
  // A 128-bit XXH3 digest, seeded at random per process so that a model
  // cannot be made to collide with another's on purpose.
  struct Key {
    uint64_t low = 0, high = 0;
    bool operator==(const Key&) const = default;
  };

  // A subdivision that added nothing: the key of its options and the
  // model's triangles (SubdivisionKeyOf), and its statistics.
  struct Unrefined {
    Key subdivision;
    SubdivisionStats stats;
  };

  // What the memo holds for a key: the placement, the footprint while the
  // byte budget keeps it (else null), and the last unrefined verdict.
  struct Entry {
    Placement placement;
    std::shared_ptr<const SheetFootprint> footprint;
    std::optional<Unrefined> unrefined;
  };

  // At most `capacity` placements, and footprints of at most
  // `footprint_bytes` together (one larger than a quarter of that is not
  // kept: a huge model would evict every other).
  explicit PlacementMemo(size_t capacity, size_t footprint_bytes = 0);

  // The key of `positions` placed on the surface `surface_id` (which names
  // its sheet) with `options` (all fields but the thread count).
  Key KeyOf(std::string_view surface_id, const PlacementOptions& options,
            const std::vector<Vec3>& positions) const;

  // The key of a subdivision of a model with `triangles` (to go with the
  // placement's key): every field of `options` but the thread count and the
  // time budget, which do not change what it adds.
  Key SubdivisionKeyOf(const SubdivisionOptions& options,
                       const std::vector<std::array<uint32_t, 3>>& triangles) const;

  // The entry stored under `key`, if any (counted as a hit or a miss; a hit
  // becomes the most recent entry).
  std::optional<Entry> Find(const Key& key);
  // Stores a placement and its footprint (may be null), dropping the least
  // recently used entries past the capacity, and the least recently used
  // footprints past the byte budget. A key stored already keeps its
  // placement, and gains the footprint if it had none.
  void Store(const Key& key, const Placement& placement,
             std::shared_ptr<const SheetFootprint> footprint = nullptr);

  // Notes that the subdivision `subdivision` of the model under `key` added
  // nothing, with these statistics (replacing an earlier verdict). Nothing
  // happens if the key is not stored.
  void NoteUnrefined(const Key& key, const Key& subdivision, const SubdivisionStats& stats);
  // The statistics of `entry`'s verdict if it is for `subdivision` (then
  // counted as a subdivision skipped), else null.
  const SubdivisionStats* UnrefinedVerdict(const Entry& entry, const Key& subdivision);

  // One deformation's use of the memo, as the engine's DeformMemo: what it
  // recalls (the placement, the footprint, a subdivision that added nothing)
  // and what it learns from the result.
  class Use final : public DeformMemo {
   public:
    Use(PlacementMemo& memo, std::string_view surface_id, const DeformOptions& options,
        const Mesh& mesh);
    Use(const Use&) = delete;
    Use& operator=(const Use&) = delete;

    std::optional<Placement> RecallPlacement() const override;
    std::shared_ptr<const SheetFootprint> RecallFootprint() const override;
    std::optional<SubdivisionStats> RecallUnrefined() const override;
    bool WantsFootprint() const override { return !known_ || !known_->footprint; }
    // Stores the placement and footprint of a model seen for the first time
    // (moving the footprint out of `result`), and a subdivision that added
    // nothing.
    void Learn(DeformResult& result) override;

    bool placement_reused() const { return known_.has_value(); }
    bool subdivision_reused() const { return unrefined_ != nullptr; }

   private:
    PlacementMemo& memo_;
    Key placed_;
    std::optional<Entry> known_;
    std::optional<Key> subdivision_;
    const SubdivisionStats* unrefined_ = nullptr;  // in known_'s verdict
  };

  PlacementMemoStats stats() const;

 private:
  struct KeyHash {
    size_t operator()(const Key& k) const { return static_cast<size_t>(k.low); }
  };
  using Entries = std::list<std::pair<Key, Entry>>;

  void Forget(Entries::iterator at);  // drops an entry's footprint (under the lock)
  void KeepWithinBudget();            // under the lock

  const size_t capacity_;
  const size_t footprint_budget_;
  const uint64_t seed_;
  mutable std::mutex mutex_;
  Entries entries_;  // most recent first
  std::unordered_map<Key, Entries::iterator, KeyHash> index_;
  size_t footprint_bytes_ = 0;  // of the entries' footprints
  uint64_t hits_ = 0, misses_ = 0;
  std::atomic<uint64_t> subdivisions_skipped_{0};
};

}  // namespace surfdeform
