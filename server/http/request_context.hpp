// A request's own state in the HTTP layer, from its head to its log line,
// and where the server keeps it while the request is served.
#pragma once

#include <httplib.h>

#include <chrono>
#include <mutex>
#include <string>
#include <unordered_map>

#include "base/cancel_flag.hpp"

namespace surfdeform::http {

// The server's own state of one request, from its head to its log line,
// passed explicitly to every handler.
struct RequestContext {
  bool active = false;
  std::chrono::steady_clock::time_point start;
  std::string id;
  bool cache_hit = false;
  bool finished = false;   // logged and counted
  size_t bytes_in = 0;     // a body read by its handler (not into req.body)
  size_t body_length = 0;  // its Content-Length, as the framing checks parsed it
  double cpu_start = 0;    // the worker thread's CPU time when the head was in
  // Raised when nobody waits for the answer any more: the service's work
  // stops at its next checkpoint.
  const CancelFlag* cancel = nullptr;
};

// The contexts of the requests being served, by httplib's Request: the one
// identity that httplib gives every callback of one request (pre-routing, the
// route, post-routing, the error and exception handlers, the logger).
class RequestContexts {
 public:
  // A fresh context for `req`.
  RequestContext& Begin(const httplib::Request& req) {
    std::lock_guard lock(mutex_);
    RequestContext& c = live_[&req];
    c = RequestContext{};
    return c;
  }
  // Its context: an inactive one when none was begun (httplib refused the
  // request line or a header before pre-routing).
  RequestContext& Of(const httplib::Request& req) {
    std::lock_guard lock(mutex_);
    return live_[&req];
  }
  void End(const httplib::Request& req) {
    std::lock_guard lock(mutex_);
    live_.erase(&req);
  }

 private:
  std::mutex mutex_;
  // Nodes: a context stays where it is while others come and go.
  std::unordered_map<const httplib::Request*, RequestContext> live_;
};

}  // namespace surfdeform::http
