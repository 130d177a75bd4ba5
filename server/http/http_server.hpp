// The HTTP front of the service (cpp-httplib): routes, request framing checks,
// problem+json errors, CORS, request ids, Server-Timing, ETags, access logs,
// metrics, readiness and graceful shutdown. Thin: it parses the HTTP
// envelope, calls Service, and encodes the reply.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "service/metrics.hpp"
#include "service/service.hpp"

namespace surfdeform::http {

enum class LogLevel { kDebug, kInfo, kWarn, kError, kOff };

struct HttpOptions {
  std::string host = "127.0.0.1";
  int port = 8080;          // 0: any free port (see HttpServer::port)
  int worker_threads = 32;  // requests served at once (idle connections wait in the gate)
  std::vector<std::string> allowed_origins = {"*"};  // CORS; "*" = any
  int read_timeout_s = 10;
  int write_timeout_s = 10;
  int keep_alive_timeout_s = 5;
  int keep_alive_max_requests = 100;
  // Slow clients (http/connection_gate.hpp): a request head (and the start
  // of its body) must be in within head_timeout_ms, off the worker threads;
  // bodies and responses must move at min_transfer_bytes_per_s once the
  // first transfer_grace_s have passed.
  int head_timeout_ms = 10000;
  int min_transfer_bytes_per_s = 16 * 1024;
  int transfer_grace_s = 10;
  // SO_SNDBUF of each accepted connection, bytes; 0 = the kernel's
  // autotuning (up to net.ipv4.tcp_wmem's maximum, some 4 MB a connection).
  // A response that fits is handed to the kernel and frees its worker at
  // once, however slowly the client reads; a larger one holds the worker
  // until it is read or cut at the minimum rate.
  int send_buffer_bytes = 0;
  // Bodies the gate reads before a worker takes the request: at once from
  // one client address, their declared bytes in all, and the longest any
  // one may take (past the minimum rate's pace it is cut sooner).
  int max_bodies_per_address = 8;
  size_t max_body_buffer_bytes = 256u << 20;
  int max_body_seconds = 300;
  // Response bytes the gate keeps for clients that read slowly, in all.
  size_t max_output_buffer_bytes = 256u << 20;
  LogLevel log_level = LogLevel::kInfo;
  // Log lines queued for standard output; past them (its reader stalled)
  // lines are dropped and counted.
  int log_queue_lines = 8192;
  // The web viewer's folder (client/web): public/ is served at /, samples/ at
  // /samples/ and node_modules/{three,meshoptimizer} at /vendor/. Empty or missing: / is
  // a small landing page built in.
  std::string web_root;
};

class HttpServer {
 public:
  HttpServer(Service& service, HttpOptions options);
  ~HttpServer();

  // Binds the listening socket; false (with a message on stderr) on failure.
  bool Bind();
  int port() const;
  // Serves until Stop(); returns once every in-flight request has finished.
  void Run();
  // Readiness false (GET /readyz answers 503); the server keeps serving.
  void Drain();
  // Stops accepting; requests in flight finish, then Run() returns.
  void Stop();
  // Cancels the work of the requests in flight (after Stop, when they have
  // had their time): each stops at its next checkpoint with a 503.
  void Cancel();
  // A line for the server's log (JSON), through its queue: never blocks.
  void Event(const std::string& json_line);

  // One connection's bytes in, what the server wrote back out, with no
  // socket: the requests in `input` are served in turn, as on a kept-alive
  // connection, until it ends or the server closes it. For the fuzzers
  // (tests/fuzz/http_fuzzer.cpp); no Bind() needed.
  std::string ServeBytes(std::string_view input);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace surfdeform::http
