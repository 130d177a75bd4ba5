#include "service/allocator_tuning.hpp"

#include <malloc.h>

#include <atomic>

#include "engine/common/parallel.hpp"

namespace surfdeform {

namespace {
std::atomic<bool> g_large_request{false};
}  // namespace

void MarkLargeRequest() { g_large_request.store(true, std::memory_order_relaxed); }

bool ReleaseAfterLargeRequest() {
  if (!g_large_request.exchange(false, std::memory_order_relaxed)) return false;
  malloc_trim(0);
  return true;
}

void TuneAllocatorForServing(size_t mmap_threshold, size_t trim, int arenas) {
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(mmap_threshold));
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(trim));
  mallopt(M_ARENA_MAX, ResolveThreads(arenas));  // 0: one per core, as the service counts them
}

}  // namespace surfdeform
