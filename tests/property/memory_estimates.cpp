// The memory estimates are upper bounds (docs/RELIABILITY.md, item 34):
// 10,000 parameter sets drawn from a seeded generator (memory_cases.hpp:
// sampling, range, lattice factor, relax steps, tolerance, method, frames),
// each run through the service in this process; the heap it takes above
// what was live before must stay within the service's own estimate for it
// plus a fixed allowance, and one refused for its memory must have taken
// no more than the allowance. The heap is counted by this program's own
// malloc, calloc, realloc and memalign, which forward to glibc's
// (everything allocates through them: operator new, Eigen's aligned
// blocks, nlohmann). The libFuzzer target tests/fuzz/memory_fuzzer.cpp
// runs the same cases from mutated bytes under the sanitizers.
//
// Usage: memory_estimates [CASES (10000)] [SEED (1)]
// Exits 1 on the first case over its bound, printing it.
#include <malloc.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "memory_cases.hpp"

extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
void __libc_free(void*);
}

namespace {

std::atomic<long long> g_live{0};
std::atomic<long long> g_peak{0};

void* Counted(void* p) {
  if (p == nullptr) return p;
  const auto size = static_cast<long long>(malloc_usable_size(p));
  const long long live = g_live.fetch_add(size, std::memory_order_relaxed) + size;
  long long peak = g_peak.load(std::memory_order_relaxed);
  while (live > peak && !g_peak.compare_exchange_weak(peak, live, std::memory_order_relaxed)) {
  }
  return p;
}
void Uncounted(void* p) {
  if (p != nullptr) {
    g_live.fetch_sub(static_cast<long long>(malloc_usable_size(p)), std::memory_order_relaxed);
  }
}

}  // namespace

extern "C" {
void* malloc(size_t n) { return Counted(__libc_malloc(n)); }
void* calloc(size_t n, size_t size) { return Counted(__libc_calloc(n, size)); }
void* realloc(void* p, size_t n) {
  Uncounted(p);
  return Counted(__libc_realloc(p, n));
}
void free(void* p) {
  Uncounted(p);
  __libc_free(p);
}
void* memalign(size_t alignment, size_t n) { return Counted(__libc_memalign(alignment, n)); }
void* aligned_alloc(size_t alignment, size_t n) { return Counted(__libc_memalign(alignment, n)); }
int posix_memalign(void** out, size_t alignment, size_t n) {
  void* p = Counted(__libc_memalign(alignment, n));
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
}

namespace {

struct Seeded {
  std::mt19937_64 rng;
  int Int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
  double Real(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  bool Bool() { return Int(0, 1) == 1; }
};

}  // namespace

int main(int argc, char** argv) {
  const long cases = argc > 1 ? std::atol(argv[1]) : 10000;
  const unsigned long seed = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 1;
  surfdeform::Service service(surfdeform::MemoryCaseServiceOptions());
  Seeded draw{std::mt19937_64(seed)};
  long ran = 0, refused = 0;
  double worst = 0, largest = 0;
  for (long k = 0; k < cases; ++k) {
    const auto c = surfdeform::DrawMemoryCase(draw);
    if (!c) continue;
    const long long before = g_live.load();
    g_peak.store(before);
    const auto reply = surfdeform::RunMemoryCase(service, *c);
    const double peak = static_cast<double>(g_peak.load() - before);
    const bool memory = surfdeform::RefusedForMemory(reply);
    const double bound =
        memory ? surfdeform::kMemoryCaseAllowance : c->estimate + surfdeform::kMemoryCaseAllowance;
    if ((reply.ok() || memory) && peak > bound) {
      std::printf(
          "FAIL: case %ld (%s) took %.2f MB of heap, over its bound of %.2f MB "
          "(estimate %.2f MB)\n%s\n",
          k, memory ? "refused for its memory" : "served", peak / 1048576.0, bound / 1048576.0,
          c->estimate / 1048576.0, c->params.c_str());
      return 1;
    }
    ++ran;
    if (memory) ++refused;
    if (reply.ok()) {
      largest = std::max(largest, peak);
      worst = std::max(worst, peak / (c->estimate + surfdeform::kMemoryCaseAllowance));
    }
  }
  std::printf(
      "memory estimates: %ld cases, %ld refused for their memory before the work; the "
      "largest took %.1f MB, and none more than %.0f%% of its bound\n",
      ran, refused, largest / 1048576.0, 100.0 * worst);
  return 0;
}
