// glibc malloc settings for the server process.
//
// By default glibc serves blocks over a dynamic threshold (128 KiB at first)
// with fresh mmap()s and returns freed memory at the top of the heap to the
// kernel, so every request pays page faults again for its large buffers
// (mesh arrays, Draco's encoder state). Measured with bench/service_bench on
// the bunny: Draco encoding inside the service 35-42 ms with the defaults,
// 21 ms with these settings (as fast as Draco's encoder in a fresh process).
// The cost is resident memory: up to `trim` bytes of freed heap per arena
// stay mapped between requests.
#pragma once

#include <cstddef>

namespace surfdeform {

// mmap only blocks of 32 MiB and more; trim the heap only past 256 MiB free.
void TuneAllocatorForServing(size_t mmap_threshold = 32u << 20, size_t trim = 256u << 20);

}  // namespace surfdeform
