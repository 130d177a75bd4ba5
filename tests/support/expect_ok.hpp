// How the shared helpers (sample surfaces, meshes, subdivision runs) report a
// step that failed, without depending on GoogleTest: the tests link
// expect_ok_gtest.cpp (a non-fatal test failure where the helper was
// called), the benchmarks bench/expect_ok_abort.cpp (a message, then abort:
// a benchmark of a failed step measures nothing).
#pragma once

#include <string>

namespace surfdeform::testing {

void ReportFailure(const std::string& what, const char* file, int line);

// Reports `result`'s status when it is not ok, at the caller's line
// (__builtin_FILE and __builtin_LINE: clang 14 has no std::source_location
// with libstdc++ 12).
template <class R>
void ExpectOk(const R& result, const char* file = __builtin_FILE(), int line = __builtin_LINE()) {
  if (!result.ok()) ReportFailure(result.status().ToString(), file, line);
}

}  // namespace surfdeform::testing
