// surfdeform-server's flags: one table (server_flags.cpp), each flag with the
// environment variable of its name (--max-queued: SURFDEFORM_MAX_QUEUED), its
// range and its default as built.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <string>

#include "http/http_server.hpp"
#include "service/service.hpp"

namespace surfdeform {

// $XDG_DATA_HOME/surfdeform, else ~/.local/share/surfdeform, else
// ./surfdeform-data: where a server without Redis keeps uploads.
std::string DefaultDataDir();

struct ServerConfig {
  ServiceOptions service;
  http::HttpOptions http;
  SharedTierOptions shared;  // the Redis level; its url empty: none
  // Without Redis: uploads and flattened surfaces kept on disk, across
  // restarts (disk_tier.hpp), unless persist_uploads is off.
  bool persist_uploads = true;
  std::string data_dir = DefaultDataDir();
  size_t data_dir_mib = 1024;
  std::string log_level = "info";
  double drain_seconds = 0.0;  // on SIGTERM: not ready this long before stopping
  // Then, once accepting has stopped: how long requests in flight may run
  // on before their work is cancelled (each stops at its next checkpoint),
  // and how long after that the process waits before it exits regardless.
  double stop_grace_seconds = 30.0;
  double stop_timeout_seconds = 10.0;
  // Byte limits as the flags give them, in MiB (ResolveServerConfig sets the
  // limits from them).
  size_t cache_mib = ServiceLimits{}.cache_bytes >> 20;
  size_t model_cache_mib = ServiceLimits{}.model_cache_bytes >> 20;
  size_t font_cache_mib = ServiceLimits{}.font_cache_bytes >> 20;
  size_t max_font_mib = ServiceLimits{}.font.max_font_bytes >> 20;
  size_t body_mib = ServiceLimits{}.max_body_bytes >> 20;
  size_t footprint_mib = ServiceLimits{}.footprint_memo_bytes >> 20;
  size_t answer_cache_mib = ServiceLimits{}.answer_cache_bytes >> 20;
  size_t request_memory_mib = ServiceLimits{}.request_memory_bytes >> 20;
  size_t body_buffer_mib = http::HttpOptions{}.max_body_buffer_bytes >> 20;
  size_t output_buffer_mib = http::HttpOptions{}.max_output_buffer_bytes >> 20;
};

// Adds every flag to `app`, bound to `config`'s fields.
void AddServerFlags(CLI::App& app, ServerConfig* config);

// After parsing: the MiB limits in bytes, the log level, and the shared
// tier's lock, which outlives both a wait for it and a flattening.
void ResolveServerConfig(ServerConfig* config);

}  // namespace surfdeform
