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

const std::array<Metrics::CacheFamily, 3> Metrics::kCacheFamilies = {{
    {"surfdeform_model_cache_", &ServerStats::models,
     "Model lookups and uploads served from the cache.",
     "Model lookups and uploads that had to import.", "uploaded models"},
    {"surfdeform_answer_cache_", &ServerStats::answers,
     "Answers of POST /v1/deform served from the cache (or from a concurrent request's making "
     "of the same answer).",
     "Answers that had to be made (parse, deformation, encoding).", "kept answers"},
    {"surfdeform_edit_paths_", &ServerStats::edit_paths,
     "Warm-started edits that measured from the kept distance paths of the surface they started "
     "from.",
     "Warm-started edits that found no kept paths (measured afresh).", "kept distance paths"},
}};

namespace {

// The exposition's text, a metric at a time.
class Exposition {
 public:
  void Line(const std::string& text) { out_ += text + "\n"; }
  // HELP, TYPE and one unlabelled sample.
  void One(const std::string& name, const char* type, const std::string& help,
           const std::string& value) {
    Line("# HELP " + name + " " + help);
    Line("# TYPE " + name + " " + type);
    Line(name + " " + value);
  }
  // HELP, TYPE and one sample per label value.
  void Labelled(const std::string& name, const char* type, const std::string& help,
                const char* label,
                std::initializer_list<std::pair<const char*, std::string>> samples) {
    Line("# HELP " + name + " " + help);
    Line("# TYPE " + name + " " + type);
    for (const auto& [value, sample] : samples) {
      Line(name + "{" + label + "=\"" + value + "\"} " + sample);
    }
  }
  std::string Take() { return std::move(out_); }

 private:
  std::string out_;
};

std::string Count(uint64_t n) { return std::to_string(n); }

void SurfaceCache(Exposition& e, const CacheStats& c) {
  auto counter = [&](const char* name, const char* help, uint64_t value) {
    e.One(std::string("surfdeform_cache_") + name + "_total", "counter", help, Count(value));
  };
  auto gauge = [&](const char* name, const char* help, uint64_t value) {
    e.One(std::string("surfdeform_cache_") + name, "gauge", help, Count(value));
  };
  counter("hits", "Flattened-surface lookups served from the cache.", c.hits);
  counter("misses", "Flattened-surface lookups that had to flatten.", c.misses);
  counter("coalesced", "Lookups that waited for a concurrent flattening of the same surface.",
          c.coalesced);
  counter("evictions", "Entries evicted to stay within the byte budget.", c.evictions);
  counter("failures", "Flattenings that failed (never cached).", c.failures);
  gauge("bytes", "Bytes held by cached flattened surfaces.", c.bytes);
  gauge("entries", "Flattened surfaces in the cache.", c.entries);
  gauge("capacity_bytes", "The cache's byte budget.", c.capacity_bytes);
}

void CacheFamilyLines(Exposition& e, const Metrics::CacheFamily& f, const CacheStats& s) {
  const std::string p = f.prefix, items = f.items;
  e.One(p + "hits_total", "counter", f.hits, Count(s.hits));
  e.One(p + "misses_total", "counter", f.misses, Count(s.misses));
  e.One(p + "evictions_total", "counter",
        "Entries (" + items + ") evicted to stay within the byte budget.", Count(s.evictions));
  e.One(p + "bytes", "gauge", "Bytes held by " + items + " (estimated).", Count(s.bytes));
  e.One(p + "entries", "gauge", "Entries (" + items + ") in the cache.", Count(s.entries));
  e.One(p + "capacity_bytes", "gauge", "The cache's byte budget.", Count(s.capacity_bytes));
}

void AdmissionLines(Exposition& e, const AdmissionStats& a) {
  e.One("surfdeform_admission_running", "gauge", "Flatten/deform requests holding a slot.",
        Count(a.running));
  e.One("surfdeform_admission_queued", "gauge", "Requests waiting for a slot.", Count(a.queued));
  e.One("surfdeform_admission_admitted_total", "counter", "Requests given a slot.",
        Count(a.admitted));
  e.One("surfdeform_admission_waited_total", "counter",
        "Requests given a slot after waiting in the queue.", Count(a.waited));
  e.Labelled("surfdeform_admission_refused_total", "counter", "Requests refused (503), by reason.",
             "reason",
             {{"queue_full", Count(a.refused_full)}, {"queue_timeout", Count(a.refused_timeout)}});
  e.One("surfdeform_admission_service_seconds", "gauge",
        "Recent requests' time holding a slot (moving average): Retry-After comes from it.",
        Number(a.service_ms_ewma / 1000.0));
}

void ConnectionLines(Exposition& e, const ConnectionStats& c) {
  e.One("surfdeform_connections_waiting", "gauge",
        "Connections whose request head is not in yet (held off the workers).", Count(c.waiting));
  e.One("surfdeform_connections_served", "gauge", "Connections on a worker thread.",
        Count(c.served));
  e.One("surfdeform_connections_passed_total", "counter",
        "Connections whose head came in, handed to a worker.", Count(c.passed));
  e.Labelled("surfdeform_connections_closed_total", "counter",
             "Connections closed before or while being served: by the gate's deadlines and "
             "limits, or by the client, by reason.",
             "reason",
             {{"head_timeout", Count(c.head_timeout)},
              {"head_too_large", Count(c.head_too_large)},
              {"malformed_head", Count(c.malformed_head)},
              {"evicted", Count(c.evicted)},
              {"gate_full", Count(c.refused_full)},
              {"client_left", Count(c.closed_early)},
              {"slow_body", Count(c.slow_body)},
              {"slow_response", Count(c.slow_response)},
              {"keep_alive_idle", Count(c.idle)},
              {"body_not_allowed", Count(c.body_not_allowed)},
              {"bodies_refused", Count(c.bodies_refused)},
              {"cancelled", Count(c.cancelled)}});
  e.One("surfdeform_connections_reading", "gauge",
        "Request bodies being read by the connection gate, off the workers.", Count(c.reading));
  e.One("surfdeform_connections_flushing", "gauge",
        "Responses being sent by the connection gate to clients that read slowly.",
        Count(c.flushing));
  e.One("surfdeform_gate_body_buffer_bytes", "gauge",
        "Declared bytes of the bodies the gate is reading.", Count(c.body_buffer_bytes));
  e.One("surfdeform_gate_output_buffer_bytes", "gauge",
        "Response bytes the gate keeps for clients that read slowly.",
        Count(c.output_buffer_bytes));
  e.Labelled("surfdeform_gate_handled_total", "counter",
             "Connection work the gate did off the workers, by kind.", "kind",
             {{"bodies_read", Count(c.bodies_read)},
              {"responses_kept", Count(c.responses_kept)},
              {"probes", Count(c.probes)}});
}

void PlacementMemoLines(Exposition& e, const PlacementMemoStats& p) {
  e.Labelled("surfdeform_placement_memo_lookups_total", "counter",
             "Placements looked up by model, surface and options: reused (hit) or computed "
             "(miss).",
             "result", {{"hit", Count(p.hits)}, {"miss", Count(p.misses)}});
  e.One("surfdeform_placement_memo_entries", "gauge", "Placements the memo holds.",
        Count(p.entries));
  e.One("surfdeform_placement_memo_footprints", "gauge",
        "Of those, how many keep where the model's vertices lie on the sheet.",
        Count(p.footprints));
  e.One("surfdeform_placement_memo_footprint_bytes", "gauge",
        "Bytes of those footprints (at most --footprint-memo-mib).", Count(p.footprint_bytes));
  e.One("surfdeform_placement_memo_subdivisions_skipped_total", "counter",
        "Subdivisions not run: they added nothing to the same model with the same options before.",
        Count(p.subdivisions_skipped));
}

void ProcessCpuLines(Exposition& e) {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                     static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
  e.One("process_cpu_seconds_total", "counter", "User and system CPU time of the server.",
        Number(cpu));
}

// The second level (Redis), when configured.
void SecondLevelLines(Exposition& e, const SharedTierStats& s) {
  auto l2 = [&](const char* name, const char* type, const char* help, const std::string& value) {
    e.One(std::string("surfdeform_l2_") + name, type, help, value);
  };
  e.Labelled("surfdeform_l2_lookups_total", "counter",
             "Second-level (shared) cache lookups, by result.", "result",
             {{"hit", Count(s.hits)}, {"miss", Count(s.misses)}, {"corrupt", Count(s.corrupt)}});
  l2("errors_total", "counter", "Commands that timed out, failed to connect or were refused.",
     Count(s.errors));
  l2("skipped_total", "counter", "Commands not sent because the breaker was open.",
     Count(s.skipped));
  l2("writes_total", "counter", "Flattened surfaces written to the second level.", Count(s.writes));
  l2("locks_acquired_total", "counter", "Cross-replica flattening locks taken by this replica.",
     Count(s.locks_acquired));
  l2("lock_waits_total", "counter", "Waits for another replica's flattening.", Count(s.lock_waits));
  l2("lock_wait_hits_total", "counter", "Waits that ended with the other replica's surface.",
     Count(s.lock_wait_hits));
  e.Line("# HELP surfdeform_l2_command_seconds Time spent in second-level commands.");
  e.Line("# TYPE surfdeform_l2_command_seconds summary");
  e.Line("surfdeform_l2_command_seconds_sum " + Number(s.command_seconds));
  e.Line("surfdeform_l2_command_seconds_count " + Count(s.commands));
  l2("breaker_open", "gauge", "1 while the breaker stops calls to the second level.",
     s.breaker_open ? "1" : "0");
}

}  // namespace

std::string Metrics::Render(const ServerStats& stats) const {
  Exposition e;
  {
    std::lock_guard lock(mutex_);
    e.Line(
        "# HELP surfdeform_http_requests_total HTTP requests answered, by route, method and "
        "status.");
    e.Line("# TYPE surfdeform_http_requests_total counter");
    for (const auto& [key, count] : requests_) {
      const auto& [route, method, status] = key;
      e.Line("surfdeform_http_requests_total{route=\"" + route + "\",method=\"" + method +
             "\",status=\"" + std::to_string(status) + "\"} " + Count(count));
    }
    e.Line(
        "# HELP surfdeform_http_request_duration_seconds Time from the request's headers to the "
        "end of its response, by route.");
    e.Line("# TYPE surfdeform_http_request_duration_seconds histogram");
    for (const auto& [route, h] : latency_) {
      const std::string name = "surfdeform_http_request_duration_seconds";
      for (size_t k = 0; k < kBuckets.size(); ++k) {
        e.Line(name + "_bucket{route=\"" + route + "\",le=\"" + Number(kBuckets[k]) + "\"} " +
               Count(h.counts[k]));
      }
      e.Line(name + "_bucket{route=\"" + route + "\",le=\"+Inf\"} " + Count(h.count));
      e.Line(name + "_sum{route=\"" + route + "\"} " + Number(h.sum));
      e.Line(name + "_count{route=\"" + route + "\"} " + Count(h.count));
    }
    e.Line(
        "# HELP surfdeform_http_request_cpu_seconds CPU time of the worker thread that handled "
        "each request, by outcome (served: 2xx and 3xx; refused: 503; failed: other).");
    e.Line("# TYPE surfdeform_http_request_cpu_seconds summary");
    for (const auto& [outcome, cpu] : request_cpu_) {
      const std::string label = "{outcome=\"" + outcome + "\"} ";
      e.Line("surfdeform_http_request_cpu_seconds_sum" + label + Number(cpu.seconds));
      e.Line("surfdeform_http_request_cpu_seconds_count" + label + Count(cpu.count));
    }
    e.Line(
        "# HELP surfdeform_http_rejected_total Requests refused before their handler ran, by "
        "reason.");
    e.Line("# TYPE surfdeform_http_rejected_total counter");
    for (const auto& [reason, count] : rejected_) {
      e.Line("surfdeform_http_rejected_total{reason=\"" + reason + "\"} " + Count(count));
    }
    e.One("surfdeform_http_request_bytes_total", "counter", "Request body bytes received.",
          Count(bytes_in_));
    e.One("surfdeform_http_response_bytes_total", "counter", "Response body bytes sent.",
          Count(bytes_out_));
  }
  e.One("surfdeform_http_requests_in_flight", "gauge", "Requests being handled now.",
        Count(in_flight_.load(std::memory_order_relaxed)));
  SurfaceCache(e, stats.surfaces);
  for (const CacheFamily& f : kCacheFamilies) CacheFamilyLines(e, f, stats.*f.stats);
  AdmissionLines(e, stats.admission);
  ConnectionLines(e, stats.connections);
  PlacementMemoLines(e, stats.placements);
  ProcessCpuLines(e);
  e.One("surfdeform_log_lines_dropped_total", "counter",
        "Log lines dropped because the log's reader stalled and its queue was full.",
        Count(stats.log_lines_dropped));
  if (stats.shared.enabled) SecondLevelLines(e, stats.shared);
  return e.Take();
}

}  // namespace surfdeform
