// surfdeform-server: flags and environment, signals, start.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "http/http_server.hpp"
#include "server_flags.hpp"
#include "service/allocator_tuning.hpp"
#include "service/disk_tier.hpp"
#include "service/service.hpp"

namespace {

// The shared tier, when --redis names one; its log is one line per change of
// its state (the breaker opening or closing). Exit code 2 for a bad URL.
int AttachSharedTier(surfdeform::ServerConfig* config) {
  if (config->shared.url.empty()) {
    if (!config->persist_uploads) return 0;
    auto disk = surfdeform::CreateDiskTier({config->data_dir, config->data_dir_mib << 20});
    if (!disk.ok()) {
      std::cerr << "surfdeform-server: " << disk.status().message() << "\n";
      return 2;
    }
    config->service.shared_tier = std::move(*disk);
    return 0;
  }
  auto tier = surfdeform::SharedTier::Create(
      config->shared, [](const std::string& state, const std::string& detail) {
        std::cout << "{\"event\":\"shared_tier\",\"state\":\"" << state << "\",\"detail\":"
                  << nlohmann::json(detail).dump(-1, ' ', true,
                                                 nlohmann::json::error_handler_t::replace)
                  << "}" << std::endl;
      });
  if (!tier.ok()) {
    std::cerr << "surfdeform-server: " << tier.status().message() << "\n";
    return 2;
  }
  config->service.shared_tier = std::move(*tier);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  surfdeform::ServerConfig config;
  CLI::App app{
      "surfdeform-server: deforms 3D meshes along parametric surfaces over HTTP.\n"
      "Every flag can also be set by the environment variable shown beside it."};
  surfdeform::AddServerFlags(app, &config);
  CLI11_PARSE(app, argc, argv);
  surfdeform::TuneAllocatorForServing();
  surfdeform::ResolveServerConfig(&config);
  const surfdeform::http::HttpOptions& http_options = config.http;

  // Signals go to one waiting thread only (blocked everywhere else, inherited
  // by every thread started after this).
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  // A log reader that goes away must not end the server: its write fails,
  // and the log drops its lines (http/log_writer.hpp).
  std::signal(SIGPIPE, SIG_IGN);

  if (const int failed = AttachSharedTier(&config); failed != 0) return failed;
  surfdeform::Service service(config.service);
  surfdeform::http::HttpServer server(service, http_options);
  if (!server.Bind()) return 1;
  std::cout << "{\"event\":\"listening\",\"host\":\"" << http_options.host
            << "\",\"port\":" << server.port()
            << ",\"shared_tier\":" << (config.shared.url.empty() ? "false" : "true")
            << ",\"uploads_kept\":\"" << service.retention().where << "\"}" << std::endl;

  // The signal thread drains and stops the server; it is joined before the
  // server and the service are destroyed (ThreadSanitizer caught a detached
  // one still inside Stop() while main destroyed the server).
  //
  // SIGTERM: not ready for --drain-seconds (load balancers stop sending),
  // then no longer accepting, with the requests in flight given
  // --stop-grace-seconds to finish; then their work is cancelled (each stops
  // at its next checkpoint), and past --stop-timeout-seconds more the
  // process exits whatever is left (docs/RELIABILITY.md, item 35).
  std::atomic<bool> stopped_by_signal{false};
  std::atomic<bool> run_ended{false};
  std::mutex ended_mutex;
  std::condition_variable ended;
  auto wait_for_end = [&](double seconds) {
    std::unique_lock lock(ended_mutex);
    return ended.wait_for(lock, std::chrono::duration<double>(seconds),
                          [&] { return run_ended.load(); });
  };
  std::thread signal_thread([&] {
    int signal = 0;
    sigwait(&signals, &signal);
    if (run_ended) return;  // woken below: the server stopped by itself
    stopped_by_signal = true;
    server.Event("{\"event\":\"draining\",\"signal\":" + std::to_string(signal) + "}");
    server.Drain();
    std::this_thread::sleep_for(std::chrono::duration<double>(config.drain_seconds));
    server.Stop();
    if (wait_for_end(config.stop_grace_seconds)) return;
    server.Event("{\"event\":\"cancelling\",\"after_seconds\":" +
                 std::to_string(config.stop_grace_seconds) + "}");
    server.Cancel();
    if (wait_for_end(config.stop_timeout_seconds)) return;
    std::cerr << "surfdeform-server: requests still at work " << config.stop_timeout_seconds
              << " s after they were cancelled; exiting\n";
    std::_Exit(1);
  });
  server.Run();
  {
    std::lock_guard lock(ended_mutex);
    run_ended = true;
  }
  ended.notify_all();
  if (!stopped_by_signal) pthread_kill(signal_thread.native_handle(), SIGTERM);
  signal_thread.join();
  server.Event("{\"event\":\"stopped\"}");
  return stopped_by_signal ? 0 : 1;
}
