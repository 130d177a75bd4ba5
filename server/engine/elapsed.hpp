// Milliseconds since a point in time, on the steady clock: for time budgets
// and reported timings.
#pragma once

#include <chrono>

namespace surfdeform {

inline double MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The end of a time budget of `budget_ms` from `start`; none (the clock's
// end) when the budget is 0.
inline std::chrono::steady_clock::time_point DeadlineAfter(
    std::chrono::steady_clock::time_point start, double budget_ms) {
  using Clock = std::chrono::steady_clock;
  if (!(budget_ms > 0.0)) return Clock::time_point::max();
  return start + std::chrono::duration_cast<Clock::duration>(
                     std::chrono::duration<double, std::milli>(budget_ms));
}

}  // namespace surfdeform
