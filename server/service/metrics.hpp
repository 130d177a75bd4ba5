// Request metrics in the Prometheus text exposition format (version 0.0.4):
// requests by route, method and status; latency histograms by route; bytes in
// and out; requests in flight; and the surface cache's counters.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <tuple>

#include "service/admission.hpp"
#include "service/placement_memo_stats.hpp"
#include "service/shared_tier.hpp"
#include "service/single_flight_cache.hpp"

namespace surfdeform {

// The HTTP layer's connection gate (http/connection_gate.hpp): slow clients
// held off the workers and closed by its deadlines.
struct ConnectionStats {
  uint64_t waiting = 0;         // gauge: connections whose request head is not in yet
  uint64_t served = 0;          // gauge: connections on a worker
  uint64_t passed = 0;          // connections handed to a worker
  uint64_t head_timeout = 0;    // 408: the head was not in by the head timeout
  uint64_t head_too_large = 0;  // 431
  uint64_t malformed_head = 0;  // 400, 414, 431: a head that cannot be framed
  uint64_t evicted = 0;         // waited longest when the gate was full
  uint64_t refused_full = 0;    // 503: the gate was full
  uint64_t closed_early = 0;    // the client left before its head was in
  uint64_t slow_body = 0;       // shut down on a worker, by phase
  uint64_t slow_response = 0;
  uint64_t idle = 0;                 // kept alive, no next request within the keep-alive timeout
  uint64_t body_not_allowed = 0;     // 400: a body on GET, HEAD, OPTIONS or TRACE
  uint64_t bodies_refused = 0;       // 503: too many bodies from one address, or in all
  uint64_t bodies_read = 0;          // bodies the gate read before a worker took the request
  uint64_t responses_kept = 0;       // responses the gate sent for slow readers
  uint64_t probes = 0;               // GET /healthz and /readyz on the probe worker
  uint64_t cancelled = 0;            // the client hung up while its request was handled
  uint64_t reading = 0;              // gauge: bodies being read by the gate
  uint64_t flushing = 0;             // gauge: responses being sent by the gate
  uint64_t body_buffer_bytes = 0;    // gauge: declared bytes of the bodies being read
  uint64_t output_buffer_bytes = 0;  // gauge: response bytes kept for slow readers
};

// What the rest of the server reports at /metrics beside its requests: a
// snapshot of each part's counters.
struct ServerStats {
  CacheStats surfaces;  // the flattened surfaces' cache (surfdeform_cache_*)
  SharedTierStats shared;
  AdmissionStats admission;
  ConnectionStats connections;
  PlacementMemoStats placements;
  // The other byte-budgeted caches, each one family of the same counters
  // (Metrics::kCacheFamilies names them).
  CacheStats models;
  CacheStats answers;
  CacheStats edit_paths;
  uint64_t log_lines_dropped = 0;  // the log's reader stalled and its queue was full
};

class Metrics {
 public:
  // Upper bounds of the latency histogram buckets, in seconds.
  static constexpr std::array<double, 12> kBuckets = {0.001, 0.0025, 0.005, 0.01, 0.025, 0.05,
                                                      0.1,   0.25,   0.5,   1.0,  2.5,   10.0};

  void RequestStarted() { in_flight_.fetch_add(1, std::memory_order_relaxed); }
  // `cpu_seconds`: the CPU time of the worker thread that served it, summed
  // by outcome (served: 2xx and 3xx; refused: 503; failed: any other), so
  // that CPU per refused request can be set against CPU per served one.
  void RequestFinished(const std::string& route, const std::string& method, int status,
                       double seconds, double cpu_seconds, uint64_t bytes_in, uint64_t bytes_out);
  void Rejected(const std::string& reason);  // load shedding and early rejections

  // The whole exposition: the requests, then `stats` (the caches at both
  // levels, admission, connections, the placement memo), and the process's
  // CPU time, for CPU per request under load.
  std::string Render(const ServerStats& stats) const;

  // The caches rendered as one family each: their prefix, their counters in
  // ServerStats, and what their hits, misses and entries are.
  struct CacheFamily {
    const char* prefix;
    CacheStats ServerStats::*stats;
    const char* hits;
    const char* misses;
    const char* items;  // what an entry is, plural
  };
  static const std::array<CacheFamily, 3> kCacheFamilies;

 private:
  struct Histogram {
    std::array<uint64_t, kBuckets.size()> counts{};
    uint64_t count = 0;
    double sum = 0.0;
  };
  mutable std::mutex mutex_;
  std::map<std::tuple<std::string, std::string, int>, uint64_t> requests_;
  std::map<std::string, Histogram> latency_;
  std::map<std::string, uint64_t> rejected_;
  struct CpuSum {
    uint64_t count = 0;
    double seconds = 0.0;
  };
  std::map<std::string, CpuSum> request_cpu_;  // by outcome
  uint64_t bytes_in_ = 0;
  uint64_t bytes_out_ = 0;
  std::atomic<int64_t> in_flight_{0};
};

}  // namespace surfdeform
