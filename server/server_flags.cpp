#include "server_flags.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace surfdeform {
namespace {

// "--max-queued" -> "SURFDEFORM_MAX_QUEUED".
std::string EnvName(const std::string& flag) {
  std::string env = "SURFDEFORM_";
  for (char c : flag.substr(2)) {
    env += c == '-' ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return env;
}

// One row of the table: the flag, what it sets, what it means, and its range
// (in the range's own type, as the help prints it).
template <typename T>
CLI::Option* Flag(CLI::App& app, const std::string& name, T& value, const std::string& meaning) {
  return app.add_option(name, value, meaning)->envname(EnvName(name))->capture_default_str();
}
template <typename T, typename R>
CLI::Option* Flag(CLI::App& app, const std::string& name, T& value, const std::string& meaning,
                  R min, R max) {
  return Flag(app, name, value, meaning)->check(CLI::Range(min, max));
}

}  // namespace

std::string DefaultDataDir() {
  if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg != nullptr && xdg[0] == '/') {
    return std::string(xdg) + "/surfdeform";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && home[0] == '/') {
    return std::string(home) + "/.local/share/surfdeform";
  }
  return "surfdeform-data";
}

namespace {

http::LogLevel ParseLogLevel(const std::string& name) {
  using http::LogLevel;
  if (name == "debug") return LogLevel::kDebug;
  if (name == "warn") return LogLevel::kWarn;
  if (name == "error") return LogLevel::kError;
  if (name == "off") return LogLevel::kOff;
  return LogLevel::kInfo;
}

}  // namespace

void AddServerFlags(CLI::App& app, ServerConfig* c) {
  ServiceLimits& l = c->service.limits;
  http::HttpOptions& h = c->http;
  h.web_root = SURFDEFORM_WEB_ROOT;
  Flag(app, "--host", h.host, "Address to listen on");
  Flag(app, "--port", h.port, "Port to listen on (0: any free port)", 0, 65535);
  Flag(app, "--http-threads", h.worker_threads,
       "Worker threads: requests served at once (connections between requests wait off them, "
       "in the connection gate)",
       2, 1024);
  Flag(app, "--engine-threads", c->service.engine_threads,
       "Threads per flattening or deformation (0: one per core)", 0, 256);
  Flag(app, "--cache-mib", c->cache_mib, "Byte budget of the flattened-surface cache, MiB", 1,
       1 << 20);
  Flag(app, "--model-cache-mib", c->model_cache_mib,
       "Byte budget of the uploaded-model cache (POST /v1/models), MiB", 1, 1 << 20);
  Flag(app, "--font-dir", l.font_dir,
       "Where the built-in fonts' files are (Debian's font packages install them under "
       "/usr/share/fonts; GET /v1/fonts lists those found)");
  Flag(app, "--font-cache-mib", c->font_cache_mib,
       "Byte budget of the uploaded-font cache (POST /v1/fonts), MiB", 1, 1 << 20);
  Flag(app, "--max-font-mib", c->max_font_mib, "Largest font file POST /v1/fonts takes, MiB", 1,
       256);
  Flag(app, "--answer-cache-mib", c->answer_cache_mib,
       "Byte budget of the encoded answers of POST /v1/deform kept by their key (a repeated "
       "request is answered without work), MiB; 0: none kept (load tests of the work itself)",
       0, 1 << 20);
  Flag(app, "--glb-split-vertices", l.glb_split_vertices,
       "A Draco GLB answer of more vertices is written in pieces (one primitive each, on one "
       "quantization grid) encoded in parallel when cores are idle; 0: never",
       0, 100'000'000);
  Flag(app, "--footprint-memo-mib", c->footprint_mib,
       "Byte budget for where the vertices of models that come back lie on their sheets (24 "
       "bytes a vertex), MiB; 0: none kept",
       0, 1 << 20);
  Flag(app, "--max-body-mib", c->body_mib, "Largest request body, MiB", 1, 4096);
  Flag(app, "--max-vertices", l.max_vertices, "Largest input mesh, vertices", 1, 100'000'000);
  Flag(app, "--max-triangles", l.max_triangles, "Largest input mesh, triangles", 1, 200'000'000);
  Flag(app, "--max-surface-mesh-vertices", l.max_surface_mesh_vertices,
       "Largest surface given as a mesh (surface kind \"mesh\"), vertices after welding", 3,
       10'000'000);
  Flag(app, "--max-surface-mesh-pairs", l.max_surface_mesh_pairs,
       "Most vertex pairs a surface given as a mesh may have within max(flatten.range, 3) rings",
       1000, 1'000'000'000);
  Flag(app, "--max-grid-side", l.max_grid_side,
       "Largest flattening grid, samples per side (2..512)", 2, 512);
  Flag(app, "--max-field-side", l.max_field_side,
       "Largest field of the sheet-to-surface map (GET /v1/surfaces/{id}/field), lattice points "
       "per side",
       2, 4096);
  Flag(app, "--max-output-vertices", l.max_output_vertices,
       "Largest deformed mesh after subdivision, vertices (over it: 413)", 1, 200'000'000);
  Flag(app, "--max-output-triangles", l.max_output_triangles,
       "Largest deformed mesh after subdivision, triangles (over it: 413)", 1, 400'000'000);
  Flag(app, "--request-memory-mib", c->request_memory_mib,
       "Memory one request's work may take, MiB, estimated from its counts before the work "
       "(over it: 413 at once); it also caps the subdivision's output",
       16, 1 << 20);
  Flag(app, "--max-json-depth", l.max_json_depth, "Deepest request JSON nesting", 4, 256);
  Flag(app, "--max-json-elements", l.max_json_elements,
       "Most values (numbers, strings, arrays, objects) in one request's JSON", 1000, 100'000'000);
  Flag(app, "--max-json-elements-in-flight", l.max_json_elements_in_flight,
       "Most request JSON values held at once by all requests together (past it: 503)", 1000,
       1'000'000'000);
  Flag(app, "--max-json-string-bytes", l.max_json_string_bytes,
       "Most bytes of keys and strings in one request's JSON", 1024, 1 << 30);
  Flag(app, "--max-in-flight", l.max_in_flight,
       "Flatten/deform requests running at once (0: one per core)", 0, 4096);
  Flag(app, "--max-queued", l.max_queued,
       "Flatten/deform requests that may wait for a slot; more are refused with 503 before "
       "their body is read (-1: four per core)",
       -1, 65536);
  Flag(app, "--queue-timeout-ms", l.queue_timeout_ms,
       "The longest a request waits for a slot before 503 (milliseconds)", 0.0, 600000.0);
  Flag(app, "--flatten-budget-ms", l.flatten_time_budget_ms,
       "A flattening that takes longer than this fails with 413 (milliseconds)", 1.0, 3.6e6);
  Flag(app, "--request-budget-ms", l.request_time_budget_ms,
       "A request whose parsing, flattening, deformation and subdivision take longer than this "
       "fails with 413 (milliseconds; the encoding after them is bounded by the output size "
       "limits)",
       1.0, 3.6e6);
  Flag(app, "--allowed-origins", h.allowed_origins,
       "CORS origins allowed to call the API (\"*\": any)")
      ->delimiter(',');
  Flag(app, "--web-root", h.web_root,
       "The web viewer's folder (client/web, with npm's node_modules); empty: a landing "
       "page instead");
  Flag(app, "--read-timeout", h.read_timeout_s, "Socket read timeout, seconds", 1, 600);
  Flag(app, "--head-timeout-ms", h.head_timeout_ms,
       "A request's head (and the start of its body) must arrive within this, ms; it waits off "
       "the worker threads meanwhile",
       100, 600000);
  Flag(app, "--min-transfer-rate", h.min_transfer_bytes_per_s,
       "Bodies and responses slower than this, bytes/s, after the grace, are cut off", 1, 1 << 30);
  Flag(app, "--transfer-grace", h.transfer_grace_s,
       "Seconds a body or response may take before the minimum rate applies", 0, 3600);
  Flag(app, "--send-buffer", h.send_buffer_bytes,
       "Kernel send buffer of each connection, bytes (0: the kernel's autotuning); responses "
       "larger than it hold a worker until read or cut at the minimum rate",
       0, 1 << 30);
  Flag(app, "--max-bodies-per-address", h.max_bodies_per_address,
       "Request bodies the server reads at once from one client address (more: 503); bodies "
       "are read before a worker takes the request",
       1, 65536);
  Flag(app, "--body-buffer-mib", c->body_buffer_mib,
       "Declared bytes of the request bodies being read at once, in all, MiB (more: 503)", 1,
       1 << 20);
  Flag(app, "--max-body-seconds", h.max_body_seconds,
       "The longest any request body may take to arrive, seconds (slower than the minimum "
       "rate: cut sooner)",
       1, 86400);
  Flag(app, "--output-buffer-mib", c->output_buffer_mib,
       "Response bytes kept for clients that read slowly, in all, MiB (past it a response "
       "waits for its reader on a worker)",
       0, 1 << 20);
  Flag(app, "--keep-alive-timeout", h.keep_alive_timeout_s,
       "Idle keep-alive connections are closed after this many seconds", 1, 600);
  Flag(app, "--drain-seconds", c->drain_seconds,
       "On SIGTERM: report not ready this long before no longer accepting", 0.0, 600.0);
  Flag(app, "--stop-grace-seconds", c->stop_grace_seconds,
       "Then: how long requests in flight may run on before their work is cancelled", 0.0, 3600.0);
  Flag(app, "--stop-timeout-seconds", c->stop_timeout_seconds,
       "Then: how long the server waits for cancelled work before it exits regardless", 0.1, 600.0);
  Flag(app, "--log-queue-lines", h.log_queue_lines,
       "Log lines queued for standard output; past them (its reader stalled) lines are dropped "
       "and counted",
       1, 1 << 24);
  Flag(app, "--log-level", c->log_level, "Access and error log level")
      ->check(CLI::IsMember({"debug", "info", "warn", "error", "off"}));
  Flag(app, "--persist-uploads", c->persist_uploads,
       "Without --redis: keep uploaded models and flattened surfaces in --data-dir, so that "
       "they outlive a restart (false: in memory only)");
  Flag(app, "--data-dir", c->data_dir,
       "Where uploads and flattened surfaces are kept without --redis (one server a directory)");
  Flag(app, "--data-dir-mib", c->data_dir_mib,
       "Byte budget of --data-dir, MiB: past it the least recently used are removed", 1, 1 << 24);
  app.add_option("--redis", c->shared.url,
                 "Share flattened surfaces with other replicas through Redis: "
                 "redis://[[user]:password@]host[:port][/db] or unix:///path (empty: "
                 "in-process cache only)")
      ->envname(EnvName("--redis"));  // no default shown: a URL may carry a password
  Flag(app, "--redis-ttl-s", c->shared.ttl_s, "A flattened surface's life in Redis, seconds", 1.0,
       3.2e7);
  Flag(app, "--redis-timeout-ms", c->shared.timeout_ms,
       "Bound on connecting to Redis and on each command, milliseconds", 1.0, 60000.0);
  Flag(app, "--redis-wait-ms", c->shared.wait_ms,
       "How long a replica waits for another replica's flattening of the same surface before "
       "flattening it itself, milliseconds",
       0.0, 600000.0);
}

void ResolveServerConfig(ServerConfig* c) {
  ServiceLimits& l = c->service.limits;
  l.cache_bytes = c->cache_mib << 20;
  l.model_cache_bytes = c->model_cache_mib << 20;
  l.font_cache_bytes = c->font_cache_mib << 20;
  l.font.max_font_bytes = c->max_font_mib << 20;
  l.max_body_bytes = c->body_mib << 20;
  l.footprint_memo_bytes = c->footprint_mib << 20;
  l.answer_cache_bytes = c->answer_cache_mib << 20;
  l.request_memory_bytes = c->request_memory_mib << 20;
  c->http.max_body_buffer_bytes = c->body_buffer_mib << 20;
  c->http.max_output_buffer_bytes = c->output_buffer_mib << 20;
  c->http.log_level = ParseLogLevel(c->log_level);
  c->shared.lock_ms = std::max(c->shared.wait_ms, l.flatten_time_budget_ms) + 1000;
}

}  // namespace surfdeform
