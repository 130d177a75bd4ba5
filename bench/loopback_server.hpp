// The real server, in process, on a free loopback port, for the benchmarks
// that time requests end to end (service_bench, edit_request_bench).
#pragma once

#include <memory>
#include <string>
#include <thread>

#include "http/http_server.hpp"
#include "service/service.hpp"

namespace surfdeform::bench {

class LoopbackServer {
 public:
  // Binds and starts serving; ok() says whether it could bind.
  explicit LoopbackServer(const ServiceOptions& options);
  ~LoopbackServer();
  LoopbackServer(const LoopbackServer&) = delete;
  LoopbackServer& operator=(const LoopbackServer&) = delete;

  bool ok() const { return running_; }
  int port() const { return server_->port(); }

 private:
  std::unique_ptr<Service> service_;
  std::unique_ptr<http::HttpServer> server_;
  std::thread runner_;
  bool running_ = false;
};

// Server-Timing "name;dur=1.2, ..." -> the value of `name` (0 if absent).
double Phase(const std::string& timing, const std::string& name);

}  // namespace surfdeform::bench
