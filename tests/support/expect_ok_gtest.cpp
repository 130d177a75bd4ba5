// The tests' ReportFailure (support/expect_ok.hpp): a non-fatal failure of
// the running test, at the helper's line.
#include <gtest/gtest.h>

#include "support/expect_ok.hpp"

namespace surfdeform::testing {

void ReportFailure(const std::string& what, const std::source_location& where) {
  ADD_FAILURE_AT(where.file_name(), static_cast<int>(where.line())) << what;
}

}  // namespace surfdeform::testing
