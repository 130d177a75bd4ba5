// How the shared helpers (sample surfaces, meshes, subdivision runs) report a
// step that failed, without depending on GoogleTest: the tests link
// expect_ok_gtest.cpp (a non-fatal test failure where the helper was
// called), the benchmarks bench/expect_ok_abort.cpp (a message, then abort:
// a benchmark of a failed step measures nothing).
#pragma once

#include <source_location>
#include <string>

namespace surfdeform::testing {

void ReportFailure(const std::string& what, const std::source_location& where);

// Reports `result`'s status when it is not ok.
template <class R>
void ExpectOk(const R& result, std::source_location where = std::source_location::current()) {
  if (!result.ok()) ReportFailure(result.status().ToString(), where);
}

}  // namespace surfdeform::testing
