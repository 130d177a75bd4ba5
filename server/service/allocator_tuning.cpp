#include "service/allocator_tuning.hpp"

#include <malloc.h>

#include <algorithm>
#include <thread>

namespace surfdeform {

void TuneAllocatorForServing(size_t mmap_threshold, size_t trim, int arenas) {
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(mmap_threshold));
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(trim));
  if (arenas <= 0) arenas = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  mallopt(M_ARENA_MAX, arenas);
}

}  // namespace surfdeform
