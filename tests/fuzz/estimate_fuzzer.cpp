// libFuzzer target: the cost of a small request. An
// input is the deformation's parameters (JSON, the first line) and a small
// mesh (the rest: OBJ, PLY, ...), typically with extreme coordinates,
// scales, centres, tolerances and outside modes. The service, with the
// published default output limits and memory budget but short time
// budgets, answers each; the target aborts (a finding) when an answer took
// longer than kBound, and libFuzzer's -rss_limit_mb bounds the memory (the
// run uses 2048 MB: ASan's shadow included, far under what the probes that
// found this took before the estimates, 0.8 to 1.2 GB of the Release
// server's own). Build with SURFDEFORM_FUZZ=ON and clang (tests/fuzz/run.sh).
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "estimate_input.hpp"

namespace {

// The request budget (the service stops at it) and slack for the work that
// follows it and for the sanitizers' slowdown.
constexpr double kBudgetMs = 1000;
constexpr auto kBound = std::chrono::milliseconds(5000);

surfdeform::Service& TheService() {
  static surfdeform::Service* service =
      new surfdeform::Service(surfdeform::EstimateServiceOptions(kBudgetMs));
  return *service;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  surfdeform::DeformRequest request;
  if (!surfdeform::EstimateRequest(std::string_view(reinterpret_cast<const char*>(data), size),
                                   &request)) {
    return 0;
  }
  const auto t0 = std::chrono::steady_clock::now();
  (void)TheService().Deform(request);
  const auto spent = std::chrono::steady_clock::now() - t0;
  if (spent > kBound) {
    std::fprintf(stderr, "a %zu-byte request took %.0f ms (bound %lld ms)\n", size,
                 std::chrono::duration<double, std::milli>(spent).count(),
                 static_cast<long long>(kBound.count()));
    std::abort();
  }
  return 0;
}
