// The benchmarks' ReportFailure (tests/support/expect_ok.hpp): a benchmark
// whose setup failed measures nothing, so it stops with the reason.
#include <cstdio>
#include <cstdlib>

#include "support/expect_ok.hpp"

namespace surfdeform::testing {

void ReportFailure(const std::string& what, const std::source_location& where) {
  std::fprintf(stderr, "%s:%u: %s\n", where.file_name(), static_cast<unsigned>(where.line()),
               what.c_str());
  std::abort();
}

}  // namespace surfdeform::testing
