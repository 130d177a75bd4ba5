// A budget that many threads take from and give back to: bytes of
// responses kept for slow readers, values of the request JSON documents in
// flight. Taking never waits: past the budget it fails and takes nothing.
#pragma once

#include <atomic>
#include <cstddef>

namespace surfdeform {

class SharedBudget {
 public:
  explicit SharedBudget(size_t max) : max_(max) {}
  SharedBudget(const SharedBudget&) = delete;
  SharedBudget& operator=(const SharedBudget&) = delete;

  // False, taking nothing, when `n` more would pass the budget.
  bool Take(size_t n) {
    size_t held = held_.load(std::memory_order_relaxed);
    do {
      if (held + n > max_) return false;
    } while (!held_.compare_exchange_weak(held, held + n, std::memory_order_relaxed));
    return true;
  }
  void Give(size_t n) { held_.fetch_sub(n, std::memory_order_relaxed); }
  size_t held() const { return held_.load(std::memory_order_relaxed); }
  size_t max() const { return max_; }

 private:
  const size_t max_;
  std::atomic<size_t> held_{0};
};

}  // namespace surfdeform
