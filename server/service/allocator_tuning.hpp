// glibc malloc settings for the server process.
//
// By default glibc serves blocks over a dynamic threshold (128 KiB at first)
// with fresh mmap()s and returns freed memory at the top of the heap to the
// kernel, so every request pays page faults again for its large buffers
// (mesh arrays, Draco's encoder state): with these settings Draco's encoding
// inside the service is as fast as in a fresh process (bench/service_bench;
// the figures are in BENCHMARKS.md).
// The cost is resident memory: up to `trim` bytes of freed heap per arena
// stay mapped between requests.
#pragma once

#include <cstddef>

namespace surfdeform {

// mmap only blocks of 32 MiB and more; trim the heap only past 256 MiB free.
void TuneAllocatorForServing(size_t mmap_threshold = 32u << 20, size_t trim = 256u << 20);

}  // namespace surfdeform
