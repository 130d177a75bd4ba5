// A flag raised to stop work that nobody waits for any more: the client of
// a request has gone, a job was cancelled, or the server is stopping. Work
// reads it where it reads its time budget, so that it stops at its next
// checkpoint.
#pragma once

#include <atomic>

namespace surfdeform {

class CancelFlag {
 public:
  CancelFlag() = default;
  // Raised when `parent` is (the server's flag under each request's).
  explicit CancelFlag(const CancelFlag* parent) : parent_(parent) {}
  CancelFlag(const CancelFlag&) = delete;
  CancelFlag& operator=(const CancelFlag&) = delete;

  void Raise() { raised_.store(true, std::memory_order_relaxed); }
  bool raised() const {
    return raised_.load(std::memory_order_relaxed) || (parent_ != nullptr && parent_->raised());
  }

 private:
  std::atomic<bool> raised_{false};
  const CancelFlag* parent_ = nullptr;
};

// Null-safe: no flag is never raised.
inline bool Cancelled(const CancelFlag* flag) { return flag != nullptr && flag->raised(); }

}  // namespace surfdeform
