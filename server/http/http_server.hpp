// The HTTP front of the service (cpp-httplib): routes, request framing checks,
// problem+json errors, CORS, request ids, Server-Timing, ETags, access logs,
// metrics, readiness and graceful shutdown. Thin: it parses the HTTP
// envelope, calls Service, and encodes the reply.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "service/metrics.hpp"
#include "service/service.hpp"

namespace surfdeform::http {

enum class LogLevel { kDebug, kInfo, kWarn, kError, kOff };

struct HttpOptions {
  std::string host = "127.0.0.1";
  int port = 8080;          // 0: any free port (see HttpServer::port)
  int worker_threads = 32;  // connections served at once (each keep-alive connection holds one)
  std::vector<std::string> allowed_origins = {"*"};  // CORS; "*" = any
  int read_timeout_s = 10;
  int write_timeout_s = 10;
  int keep_alive_timeout_s = 5;
  int keep_alive_max_requests = 100;
  LogLevel log_level = LogLevel::kInfo;
  // The web viewer's folder (client/web): public/ is served at /, samples/ at
  // /samples/ and node_modules/three at /vendor/three/. Empty or missing: / is
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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace surfdeform::http
