// The tests' ReportFailure (support/expect_ok.hpp): a non-fatal failure of
// the running test, at the helper's line.
#include <gtest/gtest.h>

#include "support/expect_ok.hpp"

namespace surfdeform::testing {

void ReportFailure(const std::string& what, const char* file, int line) {
  ADD_FAILURE_AT(file, line) << what;
}

}  // namespace surfdeform::testing
