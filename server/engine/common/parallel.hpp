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

namespace parallel_detail {
// Pins a just-spawned helper, the `index`-th of a fork (0-based), to its own
// CPU other than the caller's for its (short) life. Linux starts a new thread
// on its parent's CPU, and on the virtual machine this was measured on (KVM,
// 2 vCPUs) it often stays queued there until the parent blocks in join(),
// even with the other CPU idle, so that after an idle gap the fork ran
// serially almost every time (bench/fork_join_bench; BENCHMARKS.md). No-op where affinity cannot be
// set, or when there are fewer CPUs than helpers plus the caller.
void StartOffCallerCpu(std::thread& helper, int index);

// The calling thread's chunk runs two frames down, below a 256-byte pad, so
// that the body's temporaries do not share cache lines with the caller's
// locals. Bodies capture by reference, and the helpers read those locals
// (flags, sizes, matrices) throughout: where the caller's chunk was inlined
// beside them, its writes made every such read a miss (false sharing;
// LocateVertices on two threads took 2.7x the CPU of one, see BENCHMARKS.md).
template <typename Body>
[[gnu::noinline]] void CallBody(const Body& body, int chunk, int begin, int end) {
  body(chunk, begin, end);
}
template <typename Body>
[[gnu::noinline]] void RunBelowPad(const Body& body, int chunk, int begin, int end) {
  volatile char pad[256];
  pad[0] = 0;
  CallBody(body, chunk, begin, end);
  pad[255] = pad[0];
}
}  // namespace parallel_detail

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
    parallel_detail::StartOffCallerCpu(pool.back(), t);
  }
  const int last = threads - 1;
  const int first = static_cast<int>(static_cast<long long>(count) * last / threads);
  if (threads == 1) {
    body(last, first, count);
  } else {
    parallel_detail::RunBelowPad(body, last, first, count);
  }
  for (std::thread& th : pool) th.join();
}

}  // namespace surfdeform
