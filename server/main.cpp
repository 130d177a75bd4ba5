// surfdeform-server: flags and environment, signals, start.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "http/http_server.hpp"
#include "service/allocator_tuning.hpp"
#include "service/service.hpp"

namespace {

surfdeform::http::LogLevel ParseLogLevel(const std::string& name) {
  using surfdeform::http::LogLevel;
  if (name == "debug") return LogLevel::kDebug;
  if (name == "warn") return LogLevel::kWarn;
  if (name == "error") return LogLevel::kError;
  if (name == "off") return LogLevel::kOff;
  return LogLevel::kInfo;
}

}  // namespace

int main(int argc, char** argv) {
  surfdeform::ServiceOptions service_options;
  surfdeform::ServiceLimits& limits = service_options.limits;
  surfdeform::http::HttpOptions http_options;
  std::string log_level = "info";
  double drain_seconds = 0.0;
  size_t cache_mib = limits.cache_bytes >> 20;
  size_t body_mib = limits.max_body_bytes >> 20;
  size_t footprint_mib = limits.footprint_memo_bytes >> 20;
  size_t request_memory_mib = limits.request_memory_bytes >> 20;

  CLI::App app{
      "surfdeform-server: deforms 3D meshes along parametric surfaces over HTTP.\n"
      "Every flag can also be set by the environment variable shown beside it."};
  app.add_option("--host", http_options.host, "Address to listen on")
      ->envname("SURFDEFORM_HOST")
      ->capture_default_str();
  app.add_option("--port", http_options.port, "Port to listen on (0: any free port)")
      ->envname("SURFDEFORM_PORT")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  app.add_option("--http-threads", http_options.worker_threads,
                 "Worker threads: requests served at once (connections between requests wait off "
                 "them, in the connection gate)")
      ->envname("SURFDEFORM_HTTP_THREADS")
      ->check(CLI::Range(2, 1024))
      ->capture_default_str();
  app.add_option("--engine-threads", service_options.engine_threads,
                 "Threads per flattening or deformation (0: one per core)")
      ->envname("SURFDEFORM_ENGINE_THREADS")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  app.add_option("--cache-mib", cache_mib, "Byte budget of the flattened-surface cache, MiB")
      ->envname("SURFDEFORM_CACHE_MIB")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  app.add_option("--footprint-memo-mib", footprint_mib,
                 "Byte budget for where the vertices of models that come back lie on their "
                 "sheets (24 bytes a vertex), MiB; 0: none kept")
      ->envname("SURFDEFORM_FOOTPRINT_MEMO_MIB")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str();
  app.add_option("--max-body-mib", body_mib, "Largest request body, MiB")
      ->envname("SURFDEFORM_MAX_BODY_MIB")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  app.add_option("--max-vertices", limits.max_vertices, "Largest input mesh, vertices")
      ->envname("SURFDEFORM_MAX_VERTICES")
      ->check(CLI::Range(1, 100'000'000))
      ->capture_default_str();
  app.add_option("--max-triangles", limits.max_triangles, "Largest input mesh, triangles")
      ->envname("SURFDEFORM_MAX_TRIANGLES")
      ->check(CLI::Range(1, 200'000'000))
      ->capture_default_str();
  app.add_option("--max-grid-side", limits.max_grid_side,
                 "Largest flattening grid, samples per side (2..512)")
      ->envname("SURFDEFORM_MAX_GRID_SIDE")
      ->check(CLI::Range(2, 512))
      ->capture_default_str();
  app.add_option("--max-output-vertices", limits.max_output_vertices,
                 "Largest deformed mesh after subdivision, vertices (over it: 413)")
      ->envname("SURFDEFORM_MAX_OUTPUT_VERTICES")
      ->check(CLI::Range(1, 200'000'000))
      ->capture_default_str();
  app.add_option("--max-output-triangles", limits.max_output_triangles,
                 "Largest deformed mesh after subdivision, triangles (over it: 413)")
      ->envname("SURFDEFORM_MAX_OUTPUT_TRIANGLES")
      ->check(CLI::Range(1, 400'000'000))
      ->capture_default_str();
  app.add_option("--request-memory-mib", request_memory_mib,
                 "Memory one request's work may take, MiB, estimated from its counts before "
                 "the work (over it: 413 at once); it also caps the subdivision's output")
      ->envname("SURFDEFORM_REQUEST_MEMORY_MIB")
      ->check(CLI::Range(16, 1 << 20))
      ->capture_default_str();
  app.add_option("--max-json-depth", limits.max_json_depth, "Deepest request JSON nesting")
      ->envname("SURFDEFORM_MAX_JSON_DEPTH")
      ->check(CLI::Range(4, 256))
      ->capture_default_str();
  app.add_option("--max-in-flight", limits.max_in_flight,
                 "Flatten/deform requests running at once (0: one per core)")
      ->envname("SURFDEFORM_MAX_IN_FLIGHT")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  app.add_option("--max-queued", limits.max_queued,
                 "Flatten/deform requests that may wait for a slot; more are refused with 503 "
                 "before their body is read (-1: four per core)")
      ->envname("SURFDEFORM_MAX_QUEUED")
      ->check(CLI::Range(-1, 65536))
      ->capture_default_str();
  app.add_option("--queue-timeout-ms", limits.queue_timeout_ms,
                 "The longest a request waits for a slot before 503 (milliseconds)")
      ->envname("SURFDEFORM_QUEUE_TIMEOUT_MS")
      ->check(CLI::Range(0.0, 600000.0))
      ->capture_default_str();
  app.add_option("--flatten-budget-ms", limits.flatten_time_budget_ms,
                 "A flattening that takes longer than this fails with 413 (milliseconds)")
      ->envname("SURFDEFORM_FLATTEN_BUDGET_MS")
      ->check(CLI::Range(1.0, 3.6e6))
      ->capture_default_str();
  app.add_option("--request-budget-ms", limits.request_time_budget_ms,
                 "A request whose parsing, flattening, deformation and subdivision take longer "
                 "than this fails with 413 (milliseconds; the encoding after them is bounded by "
                 "the output size limits)")
      ->envname("SURFDEFORM_REQUEST_BUDGET_MS")
      ->check(CLI::Range(1.0, 3.6e6))
      ->capture_default_str();
  app.add_option("--allowed-origins", http_options.allowed_origins,
                 "CORS origins allowed to call the API (\"*\": any)")
      ->envname("SURFDEFORM_ALLOWED_ORIGINS")
      ->delimiter(',')
      ->capture_default_str();
  http_options.web_root = SURFDEFORM_WEB_ROOT;
  app.add_option("--web-root", http_options.web_root,
                 "The web viewer's folder (client/web, with npm's node_modules/three); empty: a "
                 "landing page instead")
      ->envname("SURFDEFORM_WEB_ROOT")
      ->capture_default_str();
  app.add_option("--read-timeout", http_options.read_timeout_s, "Socket read timeout, seconds")
      ->envname("SURFDEFORM_READ_TIMEOUT")
      ->check(CLI::Range(1, 600))
      ->capture_default_str();
  app.add_option("--head-timeout-ms", http_options.head_timeout_ms,
                 "A request's head (and the start of its body) must arrive within this, ms; "
                 "it waits off the worker threads meanwhile")
      ->envname("SURFDEFORM_HEAD_TIMEOUT_MS")
      ->check(CLI::Range(100, 600000))
      ->capture_default_str();
  app.add_option("--min-transfer-rate", http_options.min_transfer_bytes_per_s,
                 "Bodies and responses slower than this, bytes/s, after the grace, are cut off")
      ->envname("SURFDEFORM_MIN_TRANSFER_RATE")
      ->check(CLI::Range(1, 1 << 30))
      ->capture_default_str();
  app.add_option("--transfer-grace", http_options.transfer_grace_s,
                 "Seconds a body or response may take before the minimum rate applies")
      ->envname("SURFDEFORM_TRANSFER_GRACE")
      ->check(CLI::Range(0, 3600))
      ->capture_default_str();
  app.add_option("--send-buffer", http_options.send_buffer_bytes,
                 "Kernel send buffer of each connection, bytes (0: the kernel's autotuning); "
                 "responses larger than it hold a worker until read or cut at the minimum rate")
      ->envname("SURFDEFORM_SEND_BUFFER")
      ->check(CLI::Range(0, 1 << 30))
      ->capture_default_str();
  app.add_option("--keep-alive-timeout", http_options.keep_alive_timeout_s,
                 "Idle keep-alive connections are closed after this many seconds")
      ->envname("SURFDEFORM_KEEP_ALIVE_TIMEOUT")
      ->check(CLI::Range(1, 600))
      ->capture_default_str();
  app.add_option("--drain-seconds", drain_seconds,
                 "On SIGTERM: report not ready this long before no longer accepting")
      ->envname("SURFDEFORM_DRAIN_SECONDS")
      ->check(CLI::Range(0.0, 600.0))
      ->capture_default_str();
  app.add_option("--log-level", log_level, "Access and error log level")
      ->envname("SURFDEFORM_LOG_LEVEL")
      ->check(CLI::IsMember({"debug", "info", "warn", "error", "off"}))
      ->capture_default_str();
  surfdeform::SharedTierOptions shared;
  app.add_option("--redis", shared.url,
                 "Share flattened surfaces with other replicas through Redis: "
                 "redis://[[user]:password@]host[:port][/db] or unix:///path (empty: "
                 "in-process cache only)")
      ->envname("SURFDEFORM_REDIS");
  app.add_option("--redis-ttl-s", shared.ttl_s, "A flattened surface's life in Redis, seconds")
      ->envname("SURFDEFORM_REDIS_TTL_S")
      ->check(CLI::Range(1.0, 3.2e7))
      ->capture_default_str();
  app.add_option("--redis-timeout-ms", shared.timeout_ms,
                 "Bound on connecting to Redis and on each command, milliseconds")
      ->envname("SURFDEFORM_REDIS_TIMEOUT_MS")
      ->check(CLI::Range(1.0, 60000.0))
      ->capture_default_str();
  app.add_option("--redis-wait-ms", shared.wait_ms,
                 "How long a replica waits for another replica's flattening of the same "
                 "surface before flattening it itself, milliseconds")
      ->envname("SURFDEFORM_REDIS_WAIT_MS")
      ->check(CLI::Range(0.0, 600000.0))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  surfdeform::TuneAllocatorForServing();
  limits.cache_bytes = cache_mib << 20;
  limits.max_body_bytes = body_mib << 20;
  limits.footprint_memo_bytes = footprint_mib << 20;
  limits.request_memory_bytes = request_memory_mib << 20;
  http_options.log_level = ParseLogLevel(log_level);

  // Signals go to one waiting thread only (blocked everywhere else, inherited
  // by every thread started after this).
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  if (!shared.url.empty()) {
    shared.lock_ms = std::max(shared.wait_ms, limits.flatten_time_budget_ms) + 1000;
    auto tier = surfdeform::SharedTier::Create(
        shared, [](const std::string& state, const std::string& detail) {
          // One line per change of the tier's state (the breaker opening or closing).
          std::cout << "{\"event\":\"shared_tier\",\"state\":\"" << state << "\",\"detail\":"
                    << nlohmann::json(detail).dump(-1, ' ', true,
                                                   nlohmann::json::error_handler_t::replace)
                    << "}" << std::endl;
        });
    if (!tier.ok()) {
      std::cerr << "surfdeform-server: " << tier.status().message() << "\n";
      return 2;
    }
    service_options.shared_tier = std::move(*tier);
  }
  surfdeform::Service service(service_options);
  surfdeform::http::HttpServer server(service, http_options);
  if (!server.Bind()) return 1;
  std::cout << "{\"event\":\"listening\",\"host\":\"" << http_options.host
            << "\",\"port\":" << server.port()
            << ",\"shared_tier\":" << (shared.url.empty() ? "false" : "true") << "}" << std::endl;

  // The signal thread drains and stops the server; it is joined before the
  // server and the service are destroyed (ThreadSanitizer caught a detached
  // one still inside Stop() while main destroyed the server).
  std::atomic<bool> stopped_by_signal{false};
  std::atomic<bool> run_ended{false};
  std::thread signal_thread([&] {
    int signal = 0;
    sigwait(&signals, &signal);
    if (run_ended) return;  // woken below: the server stopped by itself
    stopped_by_signal = true;
    std::cout << "{\"event\":\"draining\",\"signal\":" << signal << "}" << std::endl;
    server.Drain();
    std::this_thread::sleep_for(std::chrono::duration<double>(drain_seconds));
    server.Stop();
  });
  server.Run();
  run_ended = true;
  if (!stopped_by_signal) pthread_kill(signal_thread.native_handle(), SIGTERM);
  signal_thread.join();
  std::cout << "{\"event\":\"stopped\"}" << std::endl;
  return stopped_by_signal ? 0 : 1;
}
