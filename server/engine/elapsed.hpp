// Milliseconds since a point in time, on the steady clock: for time budgets
// and reported timings.
#pragma once

#include <chrono>

namespace surfdeform {

inline double MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace surfdeform
