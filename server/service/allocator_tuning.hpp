// glibc malloc settings for the server process.
//
// By default glibc serves blocks over a dynamic threshold (128 KiB at first)
// with fresh mmap()s and returns freed memory at the top of the heap to the
// kernel, so every request pays page faults again for its large buffers
// (mesh arrays, Draco's encoder state): with these settings Draco's encoding
// inside the service is as fast as in a fresh process (bench/service_bench;
// the figures are in BENCHMARKS.md).
//
// glibc also gives threads their own arenas, up to eight per core. The
// connection gate hands each request to any of the worker threads (32 by
// default), so a request often ran in an arena that had not yet served a
// large one and paid its page faults again (a bunny's Draco encode 34 ms
// against 20 ms in a warm arena, for the first ~20 requests after start),
// and each of up to 16 arenas could keep `trim` bytes mapped. One arena per
// core keeps the arenas warm and bounds what they keep.
// The cost is resident memory: up to `trim` bytes of freed heap per arena
// stay mapped between requests.
#pragma once

#include <cstddef>

namespace surfdeform {

// mmap only blocks of 32 MiB and more; trim the heap only past 256 MiB free;
// at most `arenas` malloc arenas (0: one per core).
void TuneAllocatorForServing(size_t mmap_threshold = 32u << 20, size_t trim = 256u << 20,
                             int arenas = 0);

// After a request that took far more than most (a large body, response or
// JSON document: its many small blocks, freed, stay mapped in the arenas
// below the trim threshold), the freed memory goes back to the kernel, so
// that the server's resident size returns to its level before it.
// MarkLargeRequest() says one ended (any thread); ReleaseAfterLargeRequest()
// (the HTTP layer, once the request's own buffers are gone) trims the
// arenas when one did, and says whether it did.
inline constexpr size_t kLargeRequestBytes = 16u << 20;
void MarkLargeRequest();
bool ReleaseAfterLargeRequest();

}  // namespace surfdeform
