#include "loopback_server.hpp"

#include <cstdlib>

namespace surfdeform::bench {

LoopbackServer::LoopbackServer(const ServiceOptions& options)
    : service_(std::make_unique<Service>(options)) {
  http::HttpOptions http_options;
  http_options.port = 0;
  http_options.log_level = http::LogLevel::kOff;
  server_ = std::make_unique<http::HttpServer>(*service_, http_options);
  if (!server_->Bind()) return;
  runner_ = std::thread([this] { server_->Run(); });
  running_ = true;
}

LoopbackServer::~LoopbackServer() {
  if (!running_) return;
  server_->Stop();
  runner_.join();
}

double Phase(const std::string& timing, const std::string& name) {
  const size_t at = timing.find(name + ";dur=");
  return at == std::string::npos ? 0.0 : std::atof(timing.c_str() + at + name.size() + 5);
}

}  // namespace surfdeform::bench
