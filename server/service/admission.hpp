// Admission control for the requests that do real work (flattening,
// deformation): at most `slots` run at once, at most `queue` more wait for a
// slot in arrival order, each for at most `queue_timeout_ms`; past that a
// request is refused (503) with a Retry-After computed from the measured
// service time and the queue ahead. Waiting instead of refusing at once is
// what keeps goodput at capacity under overload: a refused client that
// retries at once makes the server spend its cores on refusals.
//
// A request that runs alone gets every core for its own data-parallel work;
// under load each gets one (Ticket::threads, ThreadsFor), so that requests do not
// fight each other's helper threads for cores.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <mutex>

#include "base/status.hpp"

namespace surfdeform {

struct AdmissionOptions {
  int slots = 2;                   // requests running at once
  int queue = 8;                   // requests waiting for a slot
  double queue_timeout_ms = 5000;  // the longest wait for a slot
  int cores = 2;                   // what a request running alone may use
};

struct AdmissionStats {
  int running = 0;
  int queued = 0;
  uint64_t admitted = 0;
  uint64_t waited = 0;           // admitted after waiting in the queue
  uint64_t refused_full = 0;     // the queue was full
  uint64_t refused_timeout = 0;  // waited queue_timeout_ms without a slot
  double service_ms_ewma = 0;    // recent requests' time holding a slot
};

class Admission {
 public:
  explicit Admission(AdmissionOptions options);

  class Ticket {
   public:
    Ticket(Ticket&& o) noexcept;
    Ticket(const Ticket&) = delete;
    Ticket& operator=(const Ticket&) = delete;
    ~Ticket();
    // Threads this request may use for its own parallel work.
    int threads() const { return threads_; }

   private:
    friend class Admission;
    Ticket(Admission* owner, int threads);
    Admission* owner_;
    int threads_;
    std::chrono::steady_clock::time_point start_;
  };

  // A slot now, or after waiting in the queue (at most `max_wait_ms`, and at
  // most the configured timeout); kUnavailable when the queue is full or the
  // wait ran out.
  Result<Ticket> Enter(double max_wait_ms = 1e300);

  // Whether a request arriving now would be refused without waiting (every
  // slot busy and the queue full): lets the HTTP layer refuse before it reads
  // a body.
  bool Full() const;

  // Seconds until a slot is likely to be free for a request arriving now:
  // the queue ahead and the running requests, at the measured service time
  // (at least 1; HTTP's Retry-After counts whole seconds).
  int RetryAfterSeconds() const;

  AdmissionStats stats() const;
  const AdmissionOptions& options() const { return options_; }

 private:
  struct Waiter {
    std::condition_variable cv;
    bool granted = false;
  };
  void Release(std::chrono::steady_clock::time_point start);
  int ThreadsLocked() const;
  Status Refusal(const char* why) const;  // with mutex_ held

  const AdmissionOptions options_;
  mutable std::mutex mutex_;
  int running_ = 0;
  std::list<Waiter*> queue_;  // arrival order
  AdmissionStats stats_;
};

// Threads for a request's own parallel work: what its ticket allows (all
// cores alone, one under load), at most `engine_threads` when that is set.
int ThreadsFor(const Admission::Ticket& ticket, int engine_threads);

}  // namespace surfdeform
