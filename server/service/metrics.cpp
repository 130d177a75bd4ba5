#include "service/metrics.hpp"

#include <sys/resource.h>

#include <cstdio>

namespace surfdeform {
namespace {

std::string Number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

}  // namespace

void Metrics::RequestFinished(const std::string& route, const std::string& method, int status,
                              double seconds, double cpu_seconds, uint64_t bytes_in,
                              uint64_t bytes_out) {
  in_flight_.fetch_sub(1, std::memory_order_relaxed);
  const char* outcome = status < 400 ? "served" : status == 503 ? "refused" : "failed";
  std::lock_guard lock(mutex_);
  CpuSum& cpu = request_cpu_[outcome];
  ++cpu.count;
  cpu.seconds += cpu_seconds;
  ++requests_[{route, method, status}];
  Histogram& h = latency_[route];
  for (size_t k = 0; k < kBuckets.size(); ++k) {
    if (seconds <= kBuckets[k]) ++h.counts[k];
  }
  ++h.count;
  h.sum += seconds;
  bytes_in_ += bytes_in;
  bytes_out_ += bytes_out;
}

void Metrics::Rejected(const std::string& reason) {
  std::lock_guard lock(mutex_);
  ++rejected_[reason];
}

std::string Metrics::Render(const CacheStats& cache, const SharedTierStats& shared,
                            const AdmissionStats& admission, const ConnectionStats& connections,
                            const PlacementMemoStats& placements, const CacheStats& models,
                            const CacheStats& answers, const CacheStats& edit_paths) const {
  std::string out;
  auto line = [&out](const std::string& text) { out += text + "\n"; };
  std::lock_guard lock(mutex_);
  line(
      "# HELP surfdeform_http_requests_total HTTP requests answered, by route, method and status.");
  line("# TYPE surfdeform_http_requests_total counter");
  for (const auto& [key, count] : requests_) {
    const auto& [route, method, status] = key;
    line("surfdeform_http_requests_total{route=\"" + route + "\",method=\"" + method +
         "\",status=\"" + std::to_string(status) + "\"} " + std::to_string(count));
  }
  line(
      "# HELP surfdeform_http_request_duration_seconds Time from the request's headers to the "
      "end of its response, by route.");
  line("# TYPE surfdeform_http_request_duration_seconds histogram");
  for (const auto& [route, h] : latency_) {
    const std::string name = "surfdeform_http_request_duration_seconds";
    for (size_t k = 0; k < kBuckets.size(); ++k) {
      line(name + "_bucket{route=\"" + route + "\",le=\"" + Number(kBuckets[k]) + "\"} " +
           std::to_string(h.counts[k]));
    }
    line(name + "_bucket{route=\"" + route + "\",le=\"+Inf\"} " + std::to_string(h.count));
    line(name + "_sum{route=\"" + route + "\"} " + Number(h.sum));
    line(name + "_count{route=\"" + route + "\"} " + std::to_string(h.count));
  }
  line(
      "# HELP surfdeform_http_request_cpu_seconds CPU time of the worker thread that handled "
      "each request, by outcome (served: 2xx and 3xx; refused: 503; failed: other).");
  line("# TYPE surfdeform_http_request_cpu_seconds summary");
  for (const auto& [outcome, cpu] : request_cpu_) {
    const std::string label = "{outcome=\"" + outcome + "\"} ";
    line("surfdeform_http_request_cpu_seconds_sum" + label + Number(cpu.seconds));
    line("surfdeform_http_request_cpu_seconds_count" + label + std::to_string(cpu.count));
  }
  line(
      "# HELP surfdeform_http_rejected_total Requests refused before their handler ran, by "
      "reason.");
  line("# TYPE surfdeform_http_rejected_total counter");
  for (const auto& [reason, count] : rejected_) {
    line("surfdeform_http_rejected_total{reason=\"" + reason + "\"} " + std::to_string(count));
  }
  line("# HELP surfdeform_http_request_bytes_total Request body bytes received.");
  line("# TYPE surfdeform_http_request_bytes_total counter");
  line("surfdeform_http_request_bytes_total " + std::to_string(bytes_in_));
  line("# HELP surfdeform_http_response_bytes_total Response body bytes sent.");
  line("# TYPE surfdeform_http_response_bytes_total counter");
  line("surfdeform_http_response_bytes_total " + std::to_string(bytes_out_));
  line("# HELP surfdeform_http_requests_in_flight Requests being handled now.");
  line("# TYPE surfdeform_http_requests_in_flight gauge");
  line("surfdeform_http_requests_in_flight " +
       std::to_string(in_flight_.load(std::memory_order_relaxed)));

  auto counter = [&](const char* name, const char* help, uint64_t value) {
    line(std::string("# HELP surfdeform_cache_") + name + "_total " + help);
    line(std::string("# TYPE surfdeform_cache_") + name + "_total counter");
    line(std::string("surfdeform_cache_") + name + "_total " + std::to_string(value));
  };
  auto gauge = [&](const char* name, const char* help, uint64_t value) {
    line(std::string("# HELP surfdeform_cache_") + name + " " + help);
    line(std::string("# TYPE surfdeform_cache_") + name + " gauge");
    line(std::string("surfdeform_cache_") + name + " " + std::to_string(value));
  };
  counter("hits", "Flattened-surface lookups served from the cache.", cache.hits);
  counter("misses", "Flattened-surface lookups that had to flatten.", cache.misses);
  counter("coalesced", "Lookups that waited for a concurrent flattening of the same surface.",
          cache.coalesced);
  counter("evictions", "Entries evicted to stay within the byte budget.", cache.evictions);
  counter("failures", "Flattenings that failed (never cached).", cache.failures);
  gauge("bytes", "Bytes held by cached flattened surfaces.", cache.bytes);
  gauge("entries", "Flattened surfaces in the cache.", cache.entries);
  gauge("capacity_bytes", "The cache's byte budget.", cache.capacity_bytes);
  // The uploaded models' cache (POST /v1/models) and the answers kept
  // (POST /v1/deform), the same counters each.
  struct CacheHelp {
    const char* hits;
    const char* misses;
    const char* items;  // what an entry is, plural
  };
  auto cache_family = [&](const std::string& prefix, const CacheStats& s, const CacheHelp& help) {
    auto one = [&](const char* name, const char* type, const std::string& text, uint64_t value) {
      const std::string full = prefix + name;
      line("# HELP " + full + " " + text);
      line("# TYPE " + full + " " + type);
      line(full + " " + std::to_string(value));
    };
    one("hits_total", "counter", help.hits, s.hits);
    one("misses_total", "counter", help.misses, s.misses);
    one("evictions_total", "counter",
        std::string("Entries (") + help.items + ") evicted to stay within the byte budget.",
        s.evictions);
    one("bytes", "gauge", std::string("Bytes held by ") + help.items + " (estimated).", s.bytes);
    one("entries", "gauge", std::string("Entries (") + help.items + ") in the cache.", s.entries);
    one("capacity_bytes", "gauge", "The cache's byte budget.", s.capacity_bytes);
  };
  cache_family("surfdeform_model_cache_", models,
               {"Model lookups and uploads served from the cache.",
                "Model lookups and uploads that had to import.", "uploaded models"});
  cache_family("surfdeform_answer_cache_", answers,
               {"Answers of POST /v1/deform served from the cache (or from a concurrent "
                "request's making of the same answer).",
                "Answers that had to be made (parse, deformation, encoding).", "kept answers"});
  cache_family(
      "surfdeform_edit_paths_", edit_paths,
      {"Warm-started edits that measured from the kept distance paths of the "
       "surface they started from.",
       "Warm-started edits that found no kept paths (measured afresh).", "kept distance paths"});

  auto plain = [&](const std::string& name, const char* type, const char* help,
                   const std::string& value) {
    line("# HELP " + name + " " + help);
    line("# TYPE " + name + " " + type);
    line(name + " " + value);
  };
  plain("surfdeform_admission_running", "gauge", "Flatten/deform requests holding a slot.",
        std::to_string(admission.running));
  plain("surfdeform_admission_queued", "gauge", "Requests waiting for a slot.",
        std::to_string(admission.queued));
  plain("surfdeform_admission_admitted_total", "counter", "Requests given a slot.",
        std::to_string(admission.admitted));
  plain("surfdeform_admission_waited_total", "counter",
        "Requests given a slot after waiting in the queue.", std::to_string(admission.waited));
  line("# HELP surfdeform_admission_refused_total Requests refused (503), by reason.");
  line("# TYPE surfdeform_admission_refused_total counter");
  line("surfdeform_admission_refused_total{reason=\"queue_full\"} " +
       std::to_string(admission.refused_full));
  line("surfdeform_admission_refused_total{reason=\"queue_timeout\"} " +
       std::to_string(admission.refused_timeout));
  plain("surfdeform_admission_service_seconds", "gauge",
        "Recent requests' time holding a slot (moving average): Retry-After comes from it.",
        Number(admission.service_ms_ewma / 1000.0));
  plain("surfdeform_connections_waiting", "gauge",
        "Connections whose request head is not in yet (held off the workers).",
        std::to_string(connections.waiting));
  plain("surfdeform_connections_served", "gauge", "Connections on a worker thread.",
        std::to_string(connections.served));
  plain("surfdeform_connections_passed_total", "counter",
        "Connections whose head came in, handed to a worker.", std::to_string(connections.passed));
  line(
      "# HELP surfdeform_connections_closed_total Connections closed before or while being "
      "served: by the gate's deadlines and limits, or by the client, by reason.");
  line("# TYPE surfdeform_connections_closed_total counter");
  for (const auto& [reason, value] :
       {std::pair<const char*, uint64_t>{"head_timeout", connections.head_timeout},
        {"head_too_large", connections.head_too_large},
        {"malformed_head", connections.malformed_head},
        {"evicted", connections.evicted},
        {"gate_full", connections.refused_full},
        {"client_left", connections.closed_early},
        {"slow_body", connections.slow_body},
        {"slow_response", connections.slow_response},
        {"keep_alive_idle", connections.idle}}) {
    line(std::string("surfdeform_connections_closed_total{reason=\"") + reason + "\"} " +
         std::to_string(value));
  }
  line(
      "# HELP surfdeform_placement_memo_lookups_total Placements looked up by model, surface and "
      "options: reused (hit) or computed (miss).");
  line("# TYPE surfdeform_placement_memo_lookups_total counter");
  line("surfdeform_placement_memo_lookups_total{result=\"hit\"} " +
       std::to_string(placements.hits));
  line("surfdeform_placement_memo_lookups_total{result=\"miss\"} " +
       std::to_string(placements.misses));
  plain("surfdeform_placement_memo_entries", "gauge", "Placements the memo holds.",
        std::to_string(placements.entries));
  plain("surfdeform_placement_memo_footprints", "gauge",
        "Of those, how many keep where the model's vertices lie on the sheet.",
        std::to_string(placements.footprints));
  plain("surfdeform_placement_memo_footprint_bytes", "gauge",
        "Bytes of those footprints (at most --footprint-memo-mib).",
        std::to_string(placements.footprint_bytes));
  plain("surfdeform_placement_memo_subdivisions_skipped_total", "counter",
        "Subdivisions not run: they added nothing to the same model with the same options before.",
        std::to_string(placements.subdivisions_skipped));
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                     static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
  plain("process_cpu_seconds_total", "counter", "User and system CPU time of the server.",
        Number(cpu));
  if (!shared.enabled) return out;

  // The second level (Redis), when configured.
  auto l2 = [&](const char* name, const char* type, const char* help, const std::string& value) {
    plain(std::string("surfdeform_l2_") + name, type, help, value);
  };
  line("# HELP surfdeform_l2_lookups_total Second-level (shared) cache lookups, by result.");
  line("# TYPE surfdeform_l2_lookups_total counter");
  line("surfdeform_l2_lookups_total{result=\"hit\"} " + std::to_string(shared.hits));
  line("surfdeform_l2_lookups_total{result=\"miss\"} " + std::to_string(shared.misses));
  line("surfdeform_l2_lookups_total{result=\"corrupt\"} " + std::to_string(shared.corrupt));
  l2("errors_total", "counter", "Commands that timed out, failed to connect or were refused.",
     std::to_string(shared.errors));
  l2("skipped_total", "counter", "Commands not sent because the breaker was open.",
     std::to_string(shared.skipped));
  l2("writes_total", "counter", "Flattened surfaces written to the second level.",
     std::to_string(shared.writes));
  l2("locks_acquired_total", "counter", "Cross-replica flattening locks taken by this replica.",
     std::to_string(shared.locks_acquired));
  l2("lock_waits_total", "counter", "Waits for another replica's flattening.",
     std::to_string(shared.lock_waits));
  l2("lock_wait_hits_total", "counter", "Waits that ended with the other replica's surface.",
     std::to_string(shared.lock_wait_hits));
  line("# HELP surfdeform_l2_command_seconds Time spent in second-level commands.");
  line("# TYPE surfdeform_l2_command_seconds summary");
  line("surfdeform_l2_command_seconds_sum " + Number(shared.command_seconds));
  line("surfdeform_l2_command_seconds_count " + std::to_string(shared.commands));
  l2("breaker_open", "gauge", "1 while the breaker stops calls to the second level.",
     shared.breaker_open ? "1" : "0");
  return out;
}

}  // namespace surfdeform
