// The placement memo's counters (service/placement_memo.hpp), apart from the
// memo so that /metrics and the service's interface need not include the
// engine's headers.
#pragma once

#include <cstddef>
#include <cstdint>

namespace surfdeform {

struct PlacementMemoStats {
  uint64_t hits = 0;
  uint64_t misses = 0;
  size_t entries = 0;
  size_t capacity = 0;
  size_t footprints = 0;       // entries that hold their footprint
  size_t footprint_bytes = 0;  // of those footprints
  size_t footprint_budget = 0;
  uint64_t subdivisions_skipped = 0;  // known to add nothing to the same model
};

}  // namespace surfdeform
