// The connection gate: slow clients never hold a worker thread for long
// (docs/RELIABILITY.md, items 8 and 30).
//
// cpp-httplib 0.11.4 gives each accepted connection a worker thread at once,
// and its read timeouts are per recv(): a client that trickles one header
// line every few seconds holds its worker for as long as it likes, and twice
// the worker count of them stop the server. The gate stands between accept()
// and the workers:
//
// - Accepted sockets wait in one epoll loop, not on a worker, until their
//   request head (through the blank line) and the first `body_window_bytes`
//   of a declared body are in the kernel's buffer (read with MSG_PEEK, so
//   httplib then parses the bytes as ever). A head not complete by
//   `head_timeout` is answered 408 and closed; one longer than
//   `max_head_bytes` 431. Heads that ask for 100-continue, declare no body,
//   a body over `max_body_bytes` or an unusable length go on at once: the
//   framing checks answer those. A head that cannot be framed (a bare LF, a
//   request line or header line httplib would refuse or misread: CheckHead
//   in request_guard.hpp) is answered at once and its connection closed,
//   so that no byte after it is read as another request.
// - Past `max_waiting` connections the one that has waited longest (an
//   idle kept-alive one first) is closed to make room: a flood of silent
//   connections cannot keep a new client, such as a liveness probe, out.
// - Between requests a kept-alive connection goes back to the epoll loop: it
//   is closed when no new request starts within `idle_timeout`, and its
//   next head has `idle_timeout + head_timeout` in all.
// - While a worker serves a connection, a watchdog holds each phase to a
//   deadline: a body or a response that moves slower than `min_bytes_per_s`
//   after `transfer_grace` is shut down.
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

#include "base/status.hpp"
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
  enum class Verdict { kWait, kPass, kTooLarge, kMalformed, kClosed };

  void Wait(int fd, int requests_left, bool kept_alive);
  void Loop();
  Verdict Inspect(int fd, size_t* seen, std::optional<Rejection>* rejection) const;
  void EvictLongestWaiting();  // while over max_waiting; on the loop's thread
  // Connections waiting past which new ones are refused: max_waiting and a
  // margin for a burst the loop has not evicted for yet.
  size_t BurstLimit() const { return options_.max_waiting + options_.max_waiting / 8; }
  void Refuse(int fd, int http_status, const Status& status);
  void CheckDeadlines(std::chrono::steady_clock::time_point now);
  void ServeOnWorker(int fd, int requests_left);

  const GateOptions options_;
  const ServeRequest serve_;
  std::unique_ptr<httplib::ThreadPool> pool_;
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
};

}  // namespace surfdeform::http
