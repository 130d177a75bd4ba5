// libFuzzer target: the memory estimates are upper bounds
// (docs/RELIABILITY.md, item 34). An input is read as a parameter set
// (memory_cases.hpp: the surface, its sampling, the flattening's range,
// lattice factor, relax steps, tolerance and method, an animation's frames).
// The service runs it; the heap it takes above what was live before (every
// allocation, counted by the sanitizer allocator's hooks) must stay within
// the service's own estimate for it and a fixed allowance for the request's
// own objects. A request the service refuses for its memory must be
// refused before the work: it may take no more than that allowance. A
// finding aborts. tests/property/memory_estimates.cpp runs the same cases
// from a seeded generator in the release build (10,000 of them in CI).
#include <fuzzer/FuzzedDataProvider.h>
#include <sanitizer/allocator_interface.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

#include "memory_cases.hpp"

namespace {

std::atomic<long long> g_live{0};
std::atomic<long long> g_peak{0};

void OnMalloc(const volatile void*, size_t size) {
  const long long live =
      g_live.fetch_add(static_cast<long long>(size)) + static_cast<long long>(size);
  long long peak = g_peak.load(std::memory_order_relaxed);
  while (live > peak && !g_peak.compare_exchange_weak(peak, live)) {
  }
}
void OnFree(const volatile void* p) {
  g_live.fetch_sub(static_cast<long long>(__sanitizer_get_allocated_size(const_cast<void*>(p))));
}

surfdeform::Service& TheService() {
  static surfdeform::Service* service = [] {
    __sanitizer_install_malloc_and_free_hooks(OnMalloc, OnFree);
    return new surfdeform::Service(surfdeform::MemoryCaseServiceOptions());
  }();
  return *service;
}

struct Bytes {
  FuzzedDataProvider& in;
  int Int(int lo, int hi) { return in.ConsumeIntegralInRange(lo, hi); }
  double Real(double lo, double hi) { return in.ConsumeFloatingPointInRange(lo, hi); }
  bool Bool() { return in.ConsumeBool(); }
};

[[noreturn]] void Finding(const char* what, const surfdeform::MemoryCase& c, double peak) {
  std::fprintf(stderr, "%s: the request took %.1f MB of heap, estimated %.1f MB (+%.1f MB)\n%s\n",
               what, peak / 1048576.0, c.estimate / 1048576.0,
               surfdeform::kMemoryCaseAllowance / 1048576.0, c.params.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  Bytes draw{in};
  const auto c = surfdeform::DrawMemoryCase(draw);
  if (!c) return 0;
  surfdeform::Service& service = TheService();
  const long long before = g_live.load();
  g_peak.store(before);
  const auto reply = surfdeform::RunMemoryCase(service, *c);
  const double peak = static_cast<double>(g_peak.load() - before);
  if (reply.ok() && peak > c->estimate + surfdeform::kMemoryCaseAllowance) {
    Finding("over its estimate", *c, peak);
  }
  if (surfdeform::RefusedForMemory(reply) && peak > surfdeform::kMemoryCaseAllowance) {
    Finding("refused for its memory after the work", *c, peak);
  }
  return 0;
}
