// Milliseconds since a point in time, on the steady clock: for time budgets
// and reported timings; and the deadline that work checks between its
// steps, which a raised cancel flag ends early.
#pragma once

#include <chrono>

#include "base/cancel_flag.hpp"

namespace surfdeform {

inline double MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// When work must stop: the end of its time budget (none: the clock's end),
// or earlier, once its cancel flag (may be null) is raised.
class Deadline {
 public:
  using Clock = std::chrono::steady_clock;
  Deadline() = default;  // never
  explicit Deadline(Clock::time_point at, const CancelFlag* cancel = nullptr)
      : at_(at), cancel_(cancel) {}

  bool Passed() const {
    return Cancelled(cancel_) || (at_ != Clock::time_point::max() && Clock::now() > at_);
  }
  const CancelFlag* cancel() const { return cancel_; }

 private:
  Clock::time_point at_ = Clock::time_point::max();
  const CancelFlag* cancel_ = nullptr;
};

// The end of a time budget of `budget_ms` from `start`; none (the clock's
// end) when the budget is 0; earlier when `cancel` is raised.
inline Deadline DeadlineAfter(std::chrono::steady_clock::time_point start, double budget_ms,
                              const CancelFlag* cancel = nullptr) {
  using Clock = std::chrono::steady_clock;
  if (!(budget_ms > 0.0)) return Deadline(Clock::time_point::max(), cancel);
  return Deadline(start + std::chrono::duration_cast<Clock::duration>(
                              std::chrono::duration<double, std::milli>(budget_ms)),
                  cancel);
}

}  // namespace surfdeform
