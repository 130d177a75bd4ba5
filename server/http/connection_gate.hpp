// The connection gate: slow clients never hold a worker thread, and one
// request cannot stop the server (docs/RELIABILITY.md, items 8, 30, 32, 33).
//
// cpp-httplib 0.11.4 gives each accepted connection a worker thread at once,
// and its read timeouts are per recv(): a client that trickles one header
// line every few seconds, or a body at a few bytes a second, holds its
// worker for as long as it likes, and twice the worker count of them stop
// the server. The gate stands between accept() and the workers, with one
// epoll thread that does every slow part of a connection's I/O:
//
// - The head. Accepted sockets wait in the epoll loop, not on a worker,
//   until their request head (through the blank line) is in the kernel's
//   buffer (read with MSG_PEEK, so that httplib then parses the bytes as
//   ever). A head not complete by `head_timeout` is answered 408 and closed;
//   one longer than `max_head_bytes` 431. A head that cannot be framed (a
//   bare LF, a request line or header line httplib would refuse or misread:
//   CheckHead in request_guard.hpp), or that declares a body on a method
//   that takes none (GET, HEAD, OPTIONS, TRACE: httplib would read the body
//   as the next request), is answered at once and its connection closed, so
//   that no byte after it is read as another request.
// - The body. A body up to `body_window_bytes` goes to the worker with its
//   head. A longer one is read here, into memory, before a worker sees the
//   request: once `transfer_grace` has passed, what is in must keep pace
//   with `min_bytes_per_s`, and all of it be in within `max_body_time`; at most
//   `max_bodies_per_address` at once from one client address and `max_body_buffer_bytes` in all
//   (past either: 503 with Retry-After). A head with "Expect: 100-continue" gets its 100 Continue
//   from here. Heads that declare no body, a body over `max_body_bytes` or an unusable length go on
//   at once: the framing checks answer those.
// - The response. What the socket does not take at once is kept (within
//   `max_output_buffer_bytes` across connections) and sent from here, within
//   `transfer_grace` plus its length at `min_bytes_per_s`; past it the
//   connection is reset.
// - Liveness. GET /healthz and /readyz go to a worker of their own
//   (`probe_workers`), which no other request uses, one request per
//   connection: no number of slow or busy connections delays them.
// - Past `max_waiting` connections the one that has waited longest (an
//   idle kept-alive one first) is closed to make room: a flood of silent
//   connections cannot keep a new client, such as a liveness probe, out.
// - Between requests a kept-alive connection goes back to the epoll loop: it
//   is closed when no new request starts within `idle_timeout`, and its
//   next head has `idle_timeout + head_timeout` in all.
// - While a worker serves a connection, a watchdog holds a body read on the
//   worker (a pipelined request's) to the minimum rate, and raises the
//   connection's cancel flag once its client hangs up while its request is
//   handled: the work stops at its next checkpoint (RequestClock).
#pragma once

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "base/cancel_flag.hpp"
#include "base/status.hpp"
#include "http/gate_stream.hpp"
#include "http/request_guard.hpp"
#include "service/metrics.hpp"

namespace surfdeform::http {

struct GateOptions {
  int workers = 32;
  size_t max_head_bytes = 32 * 1024;
  size_t body_window_bytes = 16 * 1024;
  size_t max_body_bytes = SIZE_MAX;
  std::chrono::milliseconds head_timeout{10000};
  std::chrono::milliseconds idle_timeout{5000};  // the keep-alive wait
  double min_bytes_per_s = 16 * 1024;
  std::chrono::milliseconds transfer_grace{10000};
  // Connections waiting in the gate; past it the longest waiting is closed
  // for each new one, and past max_waiting + max_waiting / 8 (a burst the
  // epoll loop has not caught up with) new ones get 503. httplib 0.11.4
  // select()s, so descriptors must stay under FD_SETSIZE (1024).
  size_t max_waiting = 512;
  int max_requests_per_connection = 100;  // keep-alive
  std::chrono::seconds read_timeout{10};  // per recv() and send(), on a worker
  std::chrono::seconds write_timeout{10};
  int send_buffer_bytes = 0;  // SO_SNDBUF of accepted sockets; 0 = the kernel's autotuning
  // Bodies read by the gate: at once from one client address, their bytes
  // in all, and the longest one may take whatever its length.
  int max_bodies_per_address = 8;
  size_t max_body_buffer_bytes = 256u << 20;
  std::chrono::milliseconds max_body_time{300000};
  // Response bytes kept for clients that read slowly, in all.
  size_t max_output_buffer_bytes = 256u << 20;
  int probe_workers = 1;  // for GET /healthz and /readyz only
  // The parent of every connection's cancel flag (the server's: raised when
  // it stops); may be null.
  const CancelFlag* stopping = nullptr;
};

// Where a request on a worker is, for the watchdog. Called on the worker
// thread that serves the connection (httplib runs a request's handlers on
// one thread); a no-op on any other thread.
namespace connection_phase {
void HeadIn(size_t content_length);  // pre-routing: the body comes next
void BodyProgress(size_t bytes);     // a handler reading its own body
void Handling();                     // the body is in; the handler works
void Responding(size_t bytes);       // the response goes out next
// The request could not be framed (httplib refused its line or headers, or
// its body is only partly read): the connection ends after this response.
void CloseAfterResponse();
// The cancel flag of the connection served on this thread: raised when its
// client hangs up while the request is handled, or when the server stops.
// Null on any other thread.
const CancelFlag* Cancel();
}  // namespace connection_phase

// One request on a connection, as httplib's Server::process_request does it:
// false when the connection cannot go on; `connection_closed` set when the
// request asked to close it.
using ServeRequest =
    std::function<bool(httplib::Stream& stream, bool close_connection, bool& connection_closed)>;

// httplib's task queue. httplib's accept loop gives it a task per accepted
// connection that ends in Admit(fd). The gate owns the connection from then
// on: it serves its requests on a worker with `serve`, hands it back to the
// epoll loop between requests (a kept-alive connection waits there, not on
// a worker), and closes it.
class ConnectionGate : public httplib::TaskQueue {
 public:
  ConnectionGate(GateOptions options, ServeRequest serve);
  ~ConnectionGate() override;

  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override;

  // Takes an accepted socket into the gate (from the accept loop's task).
  void Admit(int fd);
  ConnectionStats stats() const;

  struct Served;  // a connection on a worker

 private:
  struct Pending {
    std::chrono::steady_clock::time_point since;
    int requests_left = 0;
    bool kept_alive = false;  // back from a worker: waiting for its next request
    bool started = false;     // some bytes of the head are in
  };
  // A body read by the gate: the head and body bytes, what they must come to.
  struct Reading {
    std::string bytes;
    size_t need = 0;
    size_t head = 0;  // of `bytes`, the head's
    std::chrono::steady_clock::time_point since;
    std::string address;
    size_t declared = 0;  // the body's length, against max_body_buffer_bytes
    int requests_left = 0;
  };
  // A response the socket did not take at once, sent by the gate.
  struct Flushing {
    std::string bytes;
    size_t sent = 0;
    std::chrono::steady_clock::time_point deadline;
    int requests_left = 0;
    bool close_after = false;
  };
  enum class Verdict { kWait, kPass, kProbe, kBody, kTooLarge, kMalformed, kClosed };
  struct Inspection {
    Verdict verdict = Verdict::kWait;
    size_t seen = 0;
    size_t head_bytes = 0;
    size_t body_bytes = 0;  // declared, for kBody
    bool expect_continue = false;
    bool body_not_allowed = false;  // a body on a method that takes none
    std::optional<Rejection> rejection;
  };

  void Wait(int fd, int requests_left, bool kept_alive);
  void Loop();
  Inspection Inspect(int fd) const;
  void EvictLongestWaiting();  // while over max_waiting; on the loop's thread
  // Connections waiting past which new ones are refused: max_waiting and a
  // margin for a burst the loop has not evicted for yet.
  size_t BurstLimit() const { return options_.max_waiting + options_.max_waiting / 8; }
  void Refuse(int fd, int http_status, const Status& status);
  void CheckDeadlines(std::chrono::steady_clock::time_point now);
  void ServeOnWorker(int fd, int requests_left, std::string preloaded, bool probe);
  // The loop's handling of a waiting connection's bytes (on its thread).
  void OnWaiting(int fd);
  void StartReading(int fd, const Inspection& inspection, int requests_left);
  void OnReading(int fd);
  void EndReading(std::map<int, Reading>::iterator it);
  void StartFlushing(int fd, std::string bytes, int requests_left, bool close_after);
  void OnFlushing(int fd);
  void EndFlushing(int fd, bool ok);
  void Watch(int fd, uint32_t events);

  const GateOptions options_;
  const ServeRequest serve_;
  std::unique_ptr<httplib::ThreadPool> pool_;
  std::unique_ptr<httplib::ThreadPool> probe_pool_;
  OutputBudget output_budget_;
  int epoll_fd_ = -1;
  int wake_fd_ = -1;
  std::atomic<bool> stopping_{false};
  std::thread loop_;

  mutable std::mutex mutex_;
  std::map<int, Pending> waiting_;                 // in epoll
  std::vector<std::pair<int, Pending>> admitted_;  // not yet in epoll
  std::map<uint64_t, std::shared_ptr<Served>> served_;
  uint64_t next_served_id_ = 0;
  ConnectionStats stats_;
  // The loop thread's own: bodies being read and responses being sent, and
  // responses handed over by workers, not yet in epoll.
  std::map<int, Reading> reading_;
  std::map<std::string, int> readers_by_address_;
  size_t reading_bytes_ = 0;
  std::map<int, Flushing> flushing_;
  std::vector<std::pair<int, Flushing>> handed_over_;  // under mutex_
};

}  // namespace surfdeform::http
