// The benchmarks' ReportFailure (tests/support/expect_ok.hpp): a benchmark
// whose setup failed measures nothing, so it stops with the reason.
#include <cstdio>
#include <cstdlib>

#include "support/expect_ok.hpp"

namespace surfdeform::testing {

void ReportFailure(const std::string& what, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: %s\n", file, line, what.c_str());
  std::abort();
}

}  // namespace surfdeform::testing
