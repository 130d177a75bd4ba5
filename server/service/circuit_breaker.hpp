// A circuit breaker for a remote dependency: after `failures_to_open`
// consecutive failures it opens and callers skip the dependency for
// `open_ms`; then one caller probes it (half-open): success closes the
// breaker, failure opens it again. Thread-safe; the clock is injectable for
// tests. Each state change is reported once, to `on_change`.
#pragma once

#include <chrono>
#include <functional>
#include <mutex>

namespace surfdeform {

class CircuitBreaker {
 public:
  using Clock = std::chrono::steady_clock;
  enum class State { kClosed, kOpen, kHalfOpen };

  struct Options {
    int failures_to_open = 3;
    double open_ms = 5000;
  };

  explicit CircuitBreaker(Options options, std::function<void(State)> on_change = nullptr,
                          std::function<Clock::time_point()> now = Clock::now)
      : options_(options), on_change_(std::move(on_change)), now_(std::move(now)) {}

  // Whether a call may go ahead now. While open, false until the cool-down
  // ends; then true for exactly one caller (the probe) until it reports.
  bool Allow() {
    std::lock_guard lock(mutex_);
    if (state_ == State::kClosed) return true;
    if (state_ == State::kHalfOpen) return false;  // a probe is out
    if (now_() < reopen_at_) return false;
    SetState(State::kHalfOpen);
    return true;
  }

  void Succeeded() {
    std::lock_guard lock(mutex_);
    failures_ = 0;
    if (state_ != State::kClosed) SetState(State::kClosed);
  }

  void Failed() {
    std::lock_guard lock(mutex_);
    ++failures_;
    if (state_ == State::kHalfOpen ||
        (state_ == State::kClosed && failures_ >= options_.failures_to_open)) {
      reopen_at_ = now_() + std::chrono::duration_cast<Clock::duration>(
                                std::chrono::duration<double, std::milli>(options_.open_ms));
      SetState(State::kOpen);
    }
  }

  State state() const {
    std::lock_guard lock(mutex_);
    return state_;
  }

 private:
  void SetState(State s) {
    state_ = s;
    if (on_change_) on_change_(s);
  }

  const Options options_;
  const std::function<void(State)> on_change_;
  const std::function<Clock::time_point()> now_;
  mutable std::mutex mutex_;
  State state_ = State::kClosed;
  int failures_ = 0;
  Clock::time_point reopen_at_{};
};

}  // namespace surfdeform
