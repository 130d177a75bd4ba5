// libFuzzer target: the bytes of one connection into the real HTTP layer
// (HttpServer::ServeBytes, no socket): request lines and headers through
// httplib's parser, the framing checks, every route, multipart bodies
// through httplib's parser and the deformation's own reader, the service
// behind them with small limits so that each input runs in milliseconds.
// Build with SURFDEFORM_FUZZ=ON and clang (see tests/fuzz/run.sh).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

#include "http/http_server.hpp"
#include "http/request_guard.hpp"
#include "service/service.hpp"

namespace {

surfdeform::http::HttpServer& Server() {
  static surfdeform::Service* service = [] {
    surfdeform::ServiceOptions o;
    o.engine_threads = 1;
    o.limits.max_body_bytes = 1 << 20;
    o.limits.max_vertices = 2000;
    o.limits.max_triangles = 4000;
    o.limits.max_grid_side = 12;
    o.limits.max_output_vertices = 20000;
    o.limits.max_output_triangles = 40000;
    o.limits.flatten_time_budget_ms = 500;
    o.limits.request_time_budget_ms = 1000;
    o.limits.max_in_flight = 1;
    o.limits.max_queued = 0;
    o.limits.cache_bytes = 8u << 20;
    return new surfdeform::Service(o);
  }();
  static surfdeform::http::HttpServer* server = [] {
    surfdeform::http::HttpOptions h;
    h.log_level = surfdeform::http::LogLevel::kOff;
    h.allowed_origins = {"https://viewer.example"};
    return new surfdeform::http::HttpServer(*service, h);
  }();
  return *server;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  // The connection gate's checks on the head as it arrives, and once whole.
  (void)surfdeform::http::CheckHead(bytes, surfdeform::http::kHeadIncomplete);
  if (const size_t end = bytes.find("\r\n\r\n"); end != std::string_view::npos) {
    (void)surfdeform::http::CheckHead(bytes, end + 4);
  }
  (void)Server().ServeBytes(bytes);
  return 0;
}
