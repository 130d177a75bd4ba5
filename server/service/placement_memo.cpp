#include "service/placement_memo.hpp"

#include <xxhash.h>

#include <iterator>
#include <random>

namespace surfdeform {
namespace {

uint64_t RandomSeed() {
  std::random_device device;
  return (static_cast<uint64_t>(device()) << 32) ^ device();
}

// Feeds one field of the options to the digest (each field on its own: a
// struct's padding bytes are not part of its value).
template <typename T>
void Feed(XXH3_state_t* state, const T& value) {
  XXH3_128bits_update(state, &value, sizeof value);
}

}  // namespace

PlacementMemo::PlacementMemo(size_t capacity, size_t footprint_bytes)
    : capacity_(capacity), footprint_budget_(footprint_bytes), seed_(RandomSeed()) {}

PlacementMemo::Key PlacementMemo::KeyOf(std::string_view surface_id, const PlacementOptions& o,
                                        const std::vector<Vec3>& positions) const {
  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset_withSeed(state, seed_);
  Feed(state, surface_id.size());
  XXH3_128bits_update(state, surface_id.data(), surface_id.size());
  Feed(state, o.up);
  Feed(state, o.y_up_input);
  Feed(state, o.rigid);
  Feed(state, o.anchor);
  Feed(state, o.anchor_value);
  Feed(state, o.center_mode);
  Feed(state, o.center.x());
  Feed(state, o.center.y());
  Feed(state, o.rotation_deg);
  Feed(state, o.scale);
  Feed(state, o.fit);
  Feed(state, o.fit_margin);
  Feed(state, o.outside);
  Feed(state, positions.size());
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "positions are packed triples");
  XXH3_128bits_update(state, positions.data(), positions.size() * sizeof(Vec3));
  const XXH128_hash_t digest = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  return {digest.low64, digest.high64};
}

PlacementMemo::Key PlacementMemo::SubdivisionKeyOf(
    const SubdivisionOptions& o, const std::vector<std::array<uint32_t, 3>>& triangles) const {
  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset_withSeed(state, seed_);
  Feed(state, o.mode);
  Feed(state, o.epsilon);
  Feed(state, o.tolerance);
  Feed(state, o.max_vertices);
  Feed(state, o.max_triangles);
  Feed(state, triangles.size());
  static_assert(sizeof(triangles[0]) == 3 * sizeof(uint32_t), "triangles are packed triples");
  XXH3_128bits_update(state, triangles.data(), triangles.size() * sizeof(triangles[0]));
  const XXH128_hash_t digest = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  return {digest.low64, digest.high64};
}

std::optional<PlacementMemo::Entry> PlacementMemo::Find(const Key& key) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto at = index_.find(key);
  if (at == index_.end()) {
    ++misses_;
    return std::nullopt;
  }
  ++hits_;
  entries_.splice(entries_.begin(), entries_, at->second);
  return at->second->second;
}

void PlacementMemo::Store(const Key& key, const Placement& placement,
                          std::shared_ptr<const SheetFootprint> footprint) {
  if (capacity_ == 0) return;
  if (footprint != nullptr && footprint->bytes() > footprint_budget_ / 4) footprint = nullptr;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto at = index_.find(key);
  if (at != index_.end()) {  // stored meanwhile, or before without its footprint
    entries_.splice(entries_.begin(), entries_, at->second);
    Entry& entry = at->second->second;
    if (entry.footprint == nullptr && footprint != nullptr) {
      footprint_bytes_ += footprint->bytes();
      entry.footprint = std::move(footprint);
      KeepWithinBudget();
    }
    return;
  }
  if (footprint != nullptr) footprint_bytes_ += footprint->bytes();
  entries_.emplace_front(key, Entry{placement, std::move(footprint), std::nullopt});
  index_.emplace(key, entries_.begin());
  while (entries_.size() > capacity_) {
    Forget(std::prev(entries_.end()));
    index_.erase(entries_.back().first);
    entries_.pop_back();
  }
  KeepWithinBudget();
}

void PlacementMemo::NoteUnrefined(const Key& key, const Key& subdivision,
                                  const SubdivisionStats& stats) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto at = index_.find(key);
  if (at != index_.end()) at->second->second.unrefined = Unrefined{subdivision, stats};
}

const SubdivisionStats* PlacementMemo::UnrefinedVerdict(const Entry& entry,
                                                        const Key& subdivision) {
  if (!entry.unrefined || !(entry.unrefined->subdivision == subdivision)) return nullptr;
  subdivisions_skipped_.fetch_add(1, std::memory_order_relaxed);
  return &entry.unrefined->stats;
}

void PlacementMemo::Forget(Entries::iterator at) {
  std::shared_ptr<const SheetFootprint>& footprint = at->second.footprint;
  if (footprint == nullptr) return;
  footprint_bytes_ -= footprint->bytes();
  footprint.reset();  // a request that holds it keeps it alive
}

void PlacementMemo::KeepWithinBudget() {
  for (auto it = entries_.end(); footprint_bytes_ > footprint_budget_ && it != entries_.begin();) {
    Forget(--it);
  }
}

PlacementMemoStats PlacementMemo::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  size_t footprints = 0;
  for (const auto& [key, entry] : entries_) footprints += entry.footprint != nullptr;
  return {hits_,      misses_,          entries_.size(),   capacity_,
          footprints, footprint_bytes_, footprint_budget_, subdivisions_skipped_.load()};
}

PlacementMemo::Use::Use(PlacementMemo& memo, std::string_view surface_id,
                        const DeformOptions& options, const Mesh& mesh)
    : memo_(memo), placed_(memo.KeyOf(surface_id, options.placement, mesh.positions)) {
  known_ = memo_.Find(placed_);
  if (options.subdivision.mode != SubdivisionMode::kOff) {
    subdivision_ = memo_.SubdivisionKeyOf(options.subdivision, mesh.triangles);
    if (known_) unrefined_ = memo_.UnrefinedVerdict(*known_, *subdivision_);
  }
}

std::optional<Placement> PlacementMemo::Use::RecallPlacement() const {
  if (!known_) return std::nullopt;
  return known_->placement;
}

std::shared_ptr<const SheetFootprint> PlacementMemo::Use::RecallFootprint() const {
  return known_ ? known_->footprint : nullptr;
}

std::optional<SubdivisionStats> PlacementMemo::Use::RecallUnrefined() const {
  if (unrefined_ == nullptr) return std::nullopt;
  return *unrefined_;
}

void PlacementMemo::Use::Learn(DeformResult& result) {
  if (!known_ || !known_->footprint) {
    std::shared_ptr<const SheetFootprint> footprint;
    if (!result.footprint.location.empty()) {
      footprint = std::make_shared<const SheetFootprint>(std::move(result.footprint));
    }
    memo_.Store(placed_, result.placement, std::move(footprint));
  }
  if (result.unrefined && unrefined_ == nullptr && subdivision_) {
    memo_.NoteUnrefined(placed_, *subdivision_, result.stats.subdivision);
  }
}

}  // namespace surfdeform
