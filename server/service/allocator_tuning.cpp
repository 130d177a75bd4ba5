#include "service/allocator_tuning.hpp"

#include <malloc.h>

namespace surfdeform {

void TuneAllocatorForServing(size_t mmap_threshold, size_t trim) {
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(mmap_threshold));
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(trim));
}

}  // namespace surfdeform
