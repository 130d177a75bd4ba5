#include "service/allocator_tuning.hpp"

#include <malloc.h>

#include "engine/parallel.hpp"

namespace surfdeform {

void TuneAllocatorForServing(size_t mmap_threshold, size_t trim, int arenas) {
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(mmap_threshold));
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(trim));
  mallopt(M_ARENA_MAX, ResolveThreads(arenas));  // 0: one per core, as the service counts them
}

}  // namespace surfdeform
