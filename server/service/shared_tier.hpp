// The second level of the stores of surfaces and models, under the
// in-process LRUs: Redis, shared by replicas (through hiredis; Create), or
// a directory on this machine, which keeps uploads across restarts
// (disk_tier.hpp). Either way none of its calls can fail a request: a
// level that is unreachable, slow, full or corrupt reads as a miss.
//
// Redis: every call is bounded by a timeout and guarded by a circuit
// breaker; an unreachable Redis reads as a miss, and the caller flattens
// locally.
//
// Values are opaque bytes here; the service encodes and checks them
// (sheet_codec.hpp, model_codec.hpp). Keys are the service's.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "base/status.hpp"

namespace surfdeform {

struct SharedTierOptions {
  // redis://[[user]:password@]host[:port][/db] or unix:///path/to/redis.sock.
  // Empty: no shared tier (the default).
  std::string url;
  double ttl_s = 7 * 86400;  // a flattened surface's life in Redis
  double timeout_ms = 150;   // connecting, and each command
  double lock_ms = 30000;    // a cross-replica flattening lock expires after this
  double wait_ms = 10000;    // at most this long for another replica's flattening
  double poll_ms = 25;       // how often a waiting replica looks for the value
  int failures_to_open = 3;  // consecutive failures before the breaker opens
  double breaker_open_ms = 5000;
  size_t max_idle_connections = 16;
};

// Counters for /metrics. Latency covers every command sent.
struct SharedTierStats {
  bool enabled = false;
  const char* kind = "redis";  // or "disk"
  uint64_t hits = 0;
  uint64_t misses = 0;
  uint64_t errors = 0;   // timeouts, refused connections, error replies (e.g. OOM)
  uint64_t skipped = 0;  // calls not made because the breaker was open
  uint64_t corrupt = 0;  // values found but refused (checksum, version, shape)
  uint64_t writes = 0;
  uint64_t locks_acquired = 0;
  uint64_t lock_waits = 0;      // waits for another replica's flattening
  uint64_t lock_wait_hits = 0;  // ... that ended with its value
  uint64_t commands = 0;
  double command_seconds = 0.0;  // sum over commands
  bool breaker_open = false;
};

// How long the second level keeps a value, for replies and GET /v1/info.
struct Retention {
  const char* where = "memory";  // "memory" (no second level), "redis" or "disk"
  bool survives_restart = false;
  double ttl_s = 0;         // 0: until evicted by the byte budget
  size_t budget_bytes = 0;  // the disk's; 0: Redis's own maxmemory, or none
};

class SharedTier {
 public:
  enum class Lookup { kHit, kMiss, kUnavailable };
  enum class Lock { kAcquired, kHeldElsewhere, kUnavailable };
  // state: "up" or "down" (the breaker closed or opened), detail: why.
  using Log = std::function<void(const std::string& state, const std::string& detail)>;

  // Redis. Checks the URL only: a Redis that is down at start is not an error.
  static Result<std::unique_ptr<SharedTier>> Create(const SharedTierOptions& options, Log log);
  virtual ~SharedTier() = default;
  SharedTier(const SharedTier&) = delete;
  SharedTier& operator=(const SharedTier&) = delete;

  virtual const SharedTierOptions& options() const = 0;
  virtual Retention retention() const = 0;

  virtual Lookup Get(const std::string& key, std::string* value) = 0;
  virtual void Put(const std::string& key, std::string_view value) = 0;  // with the TTL
  // SET key token NX PX lock_ms: whether this caller now holds `key` (a
  // level of one process: always).
  virtual Lock TryLock(const std::string& key, std::string* token) = 0;
  virtual void Unlock(const std::string& key, const std::string& token) = 0;  // only if still ours
  // Whether `key` exists (false when unknown).
  virtual bool Exists(const std::string& key) = 0;

  virtual void CountCorrupt() = 0;
  virtual void CountLockWait(bool ended_with_value) = 0;
  virtual SharedTierStats stats() const = 0;

 protected:
  SharedTier() = default;
};

}  // namespace surfdeform
