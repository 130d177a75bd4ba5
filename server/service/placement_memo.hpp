// Placements of models that come back. The placement (with fit: a convex
// hull of the footprint and a bisection of the scale against the sheet's
// boundary) depends only on the model's positions, the sheet and the
// placement options, and costs ~0.6 ms of a bunny request's CPU. Load tests
// send one model again and again; a viewer sends the same model while its
// user tries other subdivisions, formats or distortion maps. The memo keys a
// placement by a digest of all three and keeps the most recent ones.
#pragma once

#include <cstddef>
#include <cstdint>
#include <list>
#include <mutex>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/geometry_types.hpp"
#include "engine/placement.hpp"
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

  explicit PlacementMemo(size_t capacity);

  // The key of `positions` placed on the surface `surface_id` (which names
  // its sheet) with `options` (all fields but the thread count).
  Key KeyOf(std::string_view surface_id, const PlacementOptions& options,
            const std::vector<Vec3>& positions) const;

  // The placement stored under `key`, if any (counted as a hit or a miss;
  // a hit becomes the most recent entry).
  std::optional<Placement> Find(const Key& key);
  // Stores a placement, dropping the least recently used past the capacity.
  void Store(const Key& key, const Placement& placement);

  PlacementMemoStats stats() const;

 private:
  struct KeyHash {
    size_t operator()(const Key& k) const { return static_cast<size_t>(k.low); }
  };
  using Entries = std::list<std::pair<Key, Placement>>;

  const size_t capacity_;
  const uint64_t seed_;
  mutable std::mutex mutex_;
  Entries entries_;  // most recent first
  std::unordered_map<Key, Entries::iterator, KeyHash> index_;
  uint64_t hits_ = 0, misses_ = 0;
};

}  // namespace surfdeform
