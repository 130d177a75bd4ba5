// A request's time budget (ServiceLimits::request_time_budget_ms): what is
// left of it, and the error once it is spent. Every room that works for a
// request reads the same clock, started when the request's work began.
#pragma once

#include <algorithm>
#include <chrono>
#include <string>

#include "base/status.hpp"
#include "engine/elapsed.hpp"

namespace surfdeform {

class RequestClock {
 public:
  using Clock = std::chrono::steady_clock;

  explicit RequestClock(double budget_ms) : start_(Clock::now()), budget_ms_(budget_ms) {}
  double remaining_ms() const { return budget_ms_ - MsSince(start_); }
  // kDeadlineExceeded when the budget is spent, naming the phase it ran out in.
  Status Check(const char* phase) const {
    const double spent = MsSince(start_);
    if (spent <= budget_ms_) return Status::Ok();
    return Status::DeadlineExceeded(
        "this server's time budget of " + std::to_string(static_cast<long long>(budget_ms_)) +
            " ms per request ran out in the request's " + phase + " (" +
            std::to_string(static_cast<long long>(spent)) +
            " ms spent); send a smaller mesh or grid, or ask for a looser subdivision",
        "request", budget_ms_, spent);
  }
  // A budget for the next phase: what is left, at most `cap` (> 0).
  double BudgetFor(double cap) const { return std::max(1.0, std::min(cap, remaining_ms())); }

 private:
  Clock::time_point start_;
  double budget_ms_;
};

// A phase's error; but a phase stopped by its own time budget once the
// request's budget is spent too reports the request's budget.
inline Status WithinBudget(const RequestClock& clock, const char* phase, Status error) {
  const bool timed_out = error.code() == ErrorCode::kDeadlineExceeded;
  Status late = clock.Check(phase);
  return timed_out && !late.ok() ? late : error;
}

}  // namespace surfdeform
