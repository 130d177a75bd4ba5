// A request's time budget (ServiceLimits::request_time_budget_ms): what is
// left of it, and the error once it is spent or once the request is
// cancelled (its client gone, the server stopping). Every room that works
// for a request reads the same clock, started when the request's work began.
#pragma once

#include <algorithm>
#include <chrono>
#include <string>

#include "base/cancel_flag.hpp"
#include "base/status.hpp"
#include "engine/common/elapsed.hpp"

namespace surfdeform {

class RequestClock {
 public:
  using Clock = std::chrono::steady_clock;

  explicit RequestClock(double budget_ms, const CancelFlag* cancel = nullptr)
      : start_(Clock::now()), budget_ms_(budget_ms), cancel_(cancel) {}
  double remaining_ms() const { return budget_ms_ - MsSince(start_); }
  // The flag that cancels the request's work (may be null): the engine's
  // options carry it.
  const CancelFlag* cancel() const { return cancel_; }
  // kUnavailable once the request is cancelled; kDeadlineExceeded when the
  // budget is spent, naming the phase it ran out in.
  Status Check(const char* phase) const {
    if (Cancelled(cancel_)) return CancelledError(phase);
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

  // What a cancelled request's work ends with (its client, if still there,
  // reads it: the server is stopping).
  static Status CancelledError(const char* phase) {
    return Status(ErrorCode::kUnavailable,
                  std::string("the request was cancelled in its ") + phase +
                      ": its client closed the connection, or the server is stopping; retry");
  }

 private:
  Clock::time_point start_;
  double budget_ms_;
  const CancelFlag* cancel_;
};

// A phase's error; but a phase stopped by its own time budget once the
// request's budget is spent too, or once the request is cancelled, reports
// that.
inline Status WithinBudget(const RequestClock& clock, const char* phase, Status error) {
  const bool timed_out = error.code() == ErrorCode::kDeadlineExceeded;
  Status late = clock.Check(phase);
  return timed_out && !late.ok() ? late : error;
}

}  // namespace surfdeform
