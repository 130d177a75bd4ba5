// A minimal fork-join loop for the engine's data-parallel passes.
#pragma once

#include <algorithm>
#include <thread>
#include <vector>

namespace surfdeform {

// Worker threads for `requested` (0 = one per core).
inline int ResolveThreads(int requested) {
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// Runs body(chunk, begin, end) over [0, count) split into at most `threads`
// contiguous chunks, one thread each (the calling thread takes the last). The
// split depends only on count and threads, so results that are combined per
// chunk in chunk order do not depend on timing.
template <typename Body>
void ParallelChunks(int count, int threads, const Body& body) {
  threads = std::max(1, std::min(threads, count));
  std::vector<std::thread> pool;
  for (int t = 0; t + 1 < threads; ++t) {
    const int b = static_cast<int>(static_cast<long long>(count) * t / threads);
    const int e = static_cast<int>(static_cast<long long>(count) * (t + 1) / threads);
    pool.emplace_back([&body, t, b, e] { body(t, b, e); });
  }
  const int last = threads - 1;
  body(last, static_cast<int>(static_cast<long long>(count) * last / threads), count);
  for (std::thread& th : pool) th.join();
}

}  // namespace surfdeform
