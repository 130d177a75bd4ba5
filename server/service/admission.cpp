#include "service/admission.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/common/elapsed.hpp"

namespace surfdeform {

using Clock = std::chrono::steady_clock;

Admission::Admission(AdmissionOptions options) : options_(options) {}

Admission::Ticket::Ticket(Admission* owner, int threads)
    : owner_(owner), threads_(threads), start_(Clock::now()) {}

Admission::Ticket::Ticket(Ticket&& o) noexcept
    : owner_(std::exchange(o.owner_, nullptr)), threads_(o.threads_), start_(o.start_) {}

Admission::Ticket::~Ticket() {
  if (owner_ != nullptr) owner_->Release(start_);
}

int Admission::ThreadsLocked() const {
  // The cores not taken by the other running requests, shared with none.
  const int others = running_ - 1;
  return std::max(1, options_.cores - others);
}

Status Admission::Refusal(const char* why) const {
  return Status(ErrorCode::kUnavailable,
                std::string("the server is busy: ") + why + " (" + std::to_string(options_.slots) +
                    " requests run at once and " + std::to_string(options_.queue) +
                    " may wait); retry after the Retry-After seconds");
}

Result<Admission::Ticket> Admission::Enter(double max_wait_ms) {
  std::unique_lock lock(mutex_);
  if (running_ < options_.slots && queue_.empty()) {
    ++running_;
    ++stats_.admitted;
    return Ticket(this, ThreadsLocked());
  }
  if (static_cast<int>(queue_.size()) >= options_.queue) {
    ++stats_.refused_full;
    return Refusal("every slot is taken and the queue is full");
  }
  Waiter me;
  queue_.push_back(&me);
  const auto it = std::prev(queue_.end());
  const double wait_ms = std::min(max_wait_ms, options_.queue_timeout_ms);
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double, std::milli>(std::max(0.0, wait_ms)));
  me.cv.wait_until(lock, deadline, [&me] { return me.granted; });
  if (!me.granted) {  // timed out (a grant after this would find it gone)
    queue_.erase(it);
    ++stats_.refused_timeout;
    return Refusal("no slot came free within the queue's time limit");
  }
  // Release() handed its slot over: running_ already counts this request.
  ++stats_.admitted;
  ++stats_.waited;
  return Ticket(this, ThreadsLocked());
}

void Admission::Release(Clock::time_point start) {
  const double ms = MsSince(start);
  std::lock_guard lock(mutex_);
  // Recent requests weigh most (about the last 20).
  stats_.service_ms_ewma =
      stats_.service_ms_ewma == 0 ? ms : 0.95 * stats_.service_ms_ewma + 0.05 * ms;
  if (!queue_.empty()) {  // the slot goes to the longest waiter
    Waiter* next = queue_.front();
    queue_.pop_front();
    next->granted = true;
    next->cv.notify_one();
    return;
  }
  --running_;
}

bool Admission::Full() const {
  std::lock_guard lock(mutex_);
  return running_ >= options_.slots && static_cast<int>(queue_.size()) >= options_.queue;
}

int Admission::RetryAfterSeconds() const {
  std::lock_guard lock(mutex_);
  // Requests ahead of a new one: the queue, and (on average) half of each
  // running request's service time is left.
  const double ahead = static_cast<double>(queue_.size()) + 0.5 * running_;
  const double seconds = ahead * stats_.service_ms_ewma / 1000.0 / std::max(1, options_.slots);
  return std::max(1, static_cast<int>(std::ceil(seconds)));
}

AdmissionStats Admission::stats() const {
  std::lock_guard lock(mutex_);
  AdmissionStats s = stats_;
  s.running = running_;
  s.queued = static_cast<int>(queue_.size());
  return s;
}

int ThreadsFor(const Admission::Ticket& ticket, int engine_threads) {
  const int t = ticket.threads();
  return engine_threads > 0 ? std::min(engine_threads, t) : t;
}

}  // namespace surfdeform
