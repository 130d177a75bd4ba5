#include "service/shared_tier.hpp"

#include <hiredis/hiredis.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <random>
#include <vector>

#include "engine/common/elapsed.hpp"
#include "service/circuit_breaker.hpp"

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

// Where Redis is, from the URL.
struct Endpoint {
  std::string host = "127.0.0.1";
  int port = 6379;
  std::string unix_path;
  std::string user;
  std::string password;
  int db = 0;
};

Result<Endpoint> ParseUrl(const std::string& url) {
  auto bad = [&url](const std::string& why) {
    return Status(ErrorCode::kInvalidArgument,
                  "the Redis URL \"" + url + "\" " + why +
                      " (expected redis://[[user]:password@]host[:port][/db] or "
                      "unix:///path/to/socket)",
                  "redis");
  };
  Endpoint e;
  if (url.rfind("unix://", 0) == 0) {
    e.unix_path = url.substr(7);
    if (e.unix_path.empty() || e.unix_path[0] != '/') return bad("needs an absolute socket path");
    return e;
  }
  if (url.rfind("redis://", 0) != 0) return bad("has an unknown scheme");
  std::string rest = url.substr(8);
  if (const size_t at = rest.rfind('@'); at != std::string::npos) {
    const std::string auth = rest.substr(0, at);
    rest = rest.substr(at + 1);
    const size_t colon = auth.find(':');
    if (colon == std::string::npos) {
      e.password = auth;
    } else {
      e.user = auth.substr(0, colon);
      e.password = auth.substr(colon + 1);
    }
  }
  if (const size_t slash = rest.find('/'); slash != std::string::npos) {
    const std::string db = rest.substr(slash + 1);
    rest = rest.substr(0, slash);
    if (!db.empty()) {
      if (db.size() > 4 || db.find_first_not_of("0123456789") != std::string::npos) {
        return bad("has a database that is not a number");
      }
      e.db = std::stoi(db);
    }
  }
  if (rest.empty()) return bad("names no host");
  if (rest[0] == '[') {  // [IPv6]:port
    const size_t close = rest.find(']');
    if (close == std::string::npos) return bad("has an unclosed IPv6 address");
    e.host = rest.substr(1, close - 1);
    rest = rest.substr(close + 1);
    if (!rest.empty() && rest[0] != ':') return bad("has text after its IPv6 address");
    rest = rest.empty() ? "" : rest.substr(1);
  } else if (const size_t colon = rest.find(':'); colon != std::string::npos) {
    e.host = rest.substr(0, colon);
    rest = rest.substr(colon + 1);
  } else {
    e.host = rest;
    rest.clear();
  }
  if (!rest.empty()) {
    if (rest.size() > 5 || rest.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(rest) < 1 || std::stoi(rest) > 65535) {
      return bad("has a port that is not 1..65535");
    }
    e.port = std::stoi(rest);
  }
  if (e.host.empty()) return bad("names no host");
  return e;
}

timeval Timeval(double ms) {
  const long long us = static_cast<long long>(ms * 1000.0);
  return timeval{static_cast<time_t>(us / 1000000), static_cast<suseconds_t>(us % 1000000)};
}

struct ReplyDeleter {
  void operator()(redisReply* r) const { freeReplyObject(r); }
};
using ReplyPtr = std::unique_ptr<redisReply, ReplyDeleter>;

struct ContextDeleter {
  void operator()(redisContext* c) const { redisFree(c); }
};
using ContextPtr = std::unique_ptr<redisContext, ContextDeleter>;

// The largest value read back: a 512 x 512 sheet is ~17 MB encoded.
constexpr long long kMaxValueBytes = 64ll << 20;

// Deletes the lock only while it still holds this caller's token.
constexpr const char* kUnlockScript =
    "if redis.call('get', KEYS[1]) == ARGV[1] then return redis.call('del', KEYS[1]) "
    "else return 0 end";

}  // namespace

class RedisTier final : public SharedTier {
 public:
  struct Impl;
  explicit RedisTier(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
  const SharedTierOptions& options() const override;
  Retention retention() const override;
  Lookup Get(const std::string& key, std::string* value) override;
  void Put(const std::string& key, std::string_view value) override;
  Lock TryLock(const std::string& key, std::string* token) override;
  void Unlock(const std::string& key, const std::string& token) override;
  bool Exists(const std::string& key) override;
  void CountCorrupt() override;
  void CountLockWait(bool ended_with_value) override;
  SharedTierStats stats() const override;

 private:
  std::unique_ptr<Impl> impl_;
};

struct RedisTier::Impl {
  Impl(SharedTierOptions o, Endpoint e, Log l)
      : options(std::move(o)),
        endpoint(std::move(e)),
        log(std::move(l)),
        breaker({options.failures_to_open, options.breaker_open_ms},
                [this](CircuitBreaker::State s) { OnBreaker(s); }) {}

  const SharedTierOptions options;
  const Endpoint endpoint;
  const Log log;
  CircuitBreaker breaker;

  std::mutex pool_mutex;
  std::vector<ContextPtr> idle;
  std::string last_error;  // under pool_mutex

  mutable std::mutex stats_mutex;
  SharedTierStats stats;

  void OnBreaker(CircuitBreaker::State s) {
    // Called with the breaker's lock held: no call back into it.
    if (s == CircuitBreaker::State::kHalfOpen) return;  // a probe: not a state users see
    const bool open = s == CircuitBreaker::State::kOpen;
    {
      std::lock_guard lock(stats_mutex);
      if (stats.breaker_open == open) return;  // a failed probe: still down
      stats.breaker_open = open;
    }
    std::string detail;
    {
      std::lock_guard lock(pool_mutex);
      detail = open ? last_error : "commands succeed again";
    }
    if (log) log(open ? "down" : "up", detail);
  }

  ContextPtr Connect(std::string* error) {
    const timeval tv = Timeval(options.timeout_ms);
    ContextPtr c(endpoint.unix_path.empty()
                     ? redisConnectWithTimeout(endpoint.host.c_str(), endpoint.port, tv)
                     : redisConnectUnixWithTimeout(endpoint.unix_path.c_str(), tv));
    if (c == nullptr) {
      *error = "cannot allocate a Redis connection";
      return nullptr;
    }
    if (c->err != 0) {
      *error = std::string("connecting to Redis: ") + c->errstr;
      return nullptr;
    }
    redisSetTimeout(c.get(), tv);
    auto setup = [&](std::vector<std::string> argv) {
      ReplyPtr r = Send(c.get(), argv);
      if (r == nullptr || r->type == REDIS_REPLY_ERROR) {
        *error = r == nullptr ? std::string("Redis: ") + c->errstr
                              : std::string("Redis refused the connection's set-up: ") + r->str;
        return false;
      }
      return true;
    };
    if (!endpoint.password.empty()) {
      std::vector<std::string> auth = {"AUTH"};
      if (!endpoint.user.empty()) auth.push_back(endpoint.user);
      auth.push_back(endpoint.password);
      if (!setup(auth)) return nullptr;
    }
    if (endpoint.db != 0 && !setup({"SELECT", std::to_string(endpoint.db)})) return nullptr;
    return c;
  }

  static ReplyPtr Send(redisContext* c, const std::vector<std::string>& argv) {
    std::vector<const char*> args;
    std::vector<size_t> lengths;
    for (const std::string& a : argv) {
      args.push_back(a.data());
      lengths.push_back(a.size());
    }
    return ReplyPtr(static_cast<redisReply*>(
        redisCommandArgv(c, static_cast<int>(args.size()), args.data(), lengths.data())));
  }

  // One command through a pooled connection. nullptr when it could not be
  // sent or answered (the breaker hears of it); an error reply is returned
  // (and counted), the connection kept.
  ReplyPtr Command(const std::vector<std::string>& argv) {
    if (!breaker.Allow()) {
      std::lock_guard lock(stats_mutex);
      ++stats.skipped;
      return nullptr;
    }
    const auto t0 = Clock::now();
    ContextPtr c;
    {
      std::lock_guard lock(pool_mutex);
      if (!idle.empty()) {
        c = std::move(idle.back());
        idle.pop_back();
      }
    }
    std::string error;
    const bool pooled = c != nullptr;
    if (!pooled) c = Connect(&error);
    ReplyPtr reply;
    if (c != nullptr) {
      reply = Send(c.get(), argv);
      if (reply == nullptr) error = std::string("Redis: ") + c->errstr;
    }
    if (reply == nullptr && pooled && MsSince(t0) < options.timeout_ms / 2) {
      // An idle connection Redis closed (a restart, its idle timeout) fails
      // at once: once more on a new one. A timeout is not retried: the
      // bound is per call.
      c = Connect(&error);
      if (c != nullptr) {
        reply = Send(c.get(), argv);
        if (reply == nullptr) error = std::string("Redis: ") + c->errstr;
      }
    }
    const double seconds = MsSince(t0) / 1000.0;
    {
      std::lock_guard lock(stats_mutex);
      ++stats.commands;
      stats.command_seconds += seconds;
      if (reply == nullptr || reply->type == REDIS_REPLY_ERROR) ++stats.errors;
    }
    if (reply == nullptr) {
      {
        std::lock_guard lock(pool_mutex);
        last_error = error;
      }
      breaker.Failed();  // the broken connection is dropped with `c`
      return nullptr;
    }
    breaker.Succeeded();
    std::lock_guard lock(pool_mutex);
    if (idle.size() < options.max_idle_connections) idle.push_back(std::move(c));
    return reply;
  }
};

Result<std::unique_ptr<SharedTier>> SharedTier::Create(const SharedTierOptions& options, Log log) {
  SURFDEFORM_ASSIGN_OR_RETURN(Endpoint endpoint, ParseUrl(options.url));
  if (!(options.ttl_s >= 1) || !(options.timeout_ms > 0) || !(options.lock_ms >= 1) ||
      !(options.wait_ms >= 0) || !(options.poll_ms > 0)) {
    return Status(ErrorCode::kInvalidArgument,
                  "the shared tier's TTL, timeout, lock and wait must be positive", "redis");
  }
  auto impl = std::make_unique<RedisTier::Impl>(options, std::move(endpoint), std::move(log));
  impl->stats.enabled = true;
  return std::unique_ptr<SharedTier>(new RedisTier(std::move(impl)));
}

const SharedTierOptions& RedisTier::options() const { return impl_->options; }

Retention RedisTier::retention() const {
  // Whether Redis keeps its values across its own restarts is its
  // persistence's (docs: appendonly yes); this server's restarts lose none.
  return Retention{"redis", true, impl_->options.ttl_s, 0};
}

SharedTier::Lookup RedisTier::Get(const std::string& key, std::string* value) {
  // GETRANGE bounds what a foreign or hostile value can make us read.
  ReplyPtr r = impl_->Command({"GETRANGE", key, "0", std::to_string(kMaxValueBytes)});
  std::lock_guard lock(impl_->stats_mutex);
  if (r == nullptr || r->type == REDIS_REPLY_ERROR) return Lookup::kUnavailable;
  if (r->type != REDIS_REPLY_STRING || r->len == 0) {  // a missing key reads as ""
    ++impl_->stats.misses;
    return Lookup::kMiss;
  }
  if (static_cast<long long>(r->len) > kMaxValueBytes) {
    ++impl_->stats.corrupt;
    return Lookup::kMiss;
  }
  ++impl_->stats.hits;
  value->assign(r->str, r->len);
  return Lookup::kHit;
}

void RedisTier::Put(const std::string& key, std::string_view value) {
  const long long ttl_ms = static_cast<long long>(impl_->options.ttl_s * 1000.0);
  ReplyPtr r = impl_->Command({"SET", key, std::string(value), "PX", std::to_string(ttl_ms)});
  if (r != nullptr && r->type != REDIS_REPLY_ERROR) {
    std::lock_guard lock(impl_->stats_mutex);
    ++impl_->stats.writes;
  }
}

SharedTier::Lock RedisTier::TryLock(const std::string& key, std::string* token) {
  thread_local std::mt19937_64 rng(std::random_device{}());
  *token = std::to_string(rng()) + std::to_string(rng());
  const long long lock_ms = static_cast<long long>(impl_->options.lock_ms);
  ReplyPtr r = impl_->Command({"SET", key, *token, "NX", "PX", std::to_string(lock_ms)});
  if (r == nullptr || r->type == REDIS_REPLY_ERROR) return Lock::kUnavailable;
  if (r->type == REDIS_REPLY_NIL) return Lock::kHeldElsewhere;
  std::lock_guard lock(impl_->stats_mutex);
  ++impl_->stats.locks_acquired;
  return Lock::kAcquired;
}

void RedisTier::Unlock(const std::string& key, const std::string& token) {
  impl_->Command({"EVAL", kUnlockScript, "1", key, token});
}

bool RedisTier::Exists(const std::string& key) {
  ReplyPtr r = impl_->Command({"EXISTS", key});
  return r != nullptr && r->type == REDIS_REPLY_INTEGER && r->integer > 0;
}

void RedisTier::CountCorrupt() {
  std::lock_guard lock(impl_->stats_mutex);
  ++impl_->stats.corrupt;
  if (impl_->stats.hits > 0) --impl_->stats.hits;  // it was counted as a hit
}

void RedisTier::CountLockWait(bool ended_with_value) {
  std::lock_guard lock(impl_->stats_mutex);
  ++impl_->stats.lock_waits;
  if (ended_with_value) ++impl_->stats.lock_wait_hits;
}

SharedTierStats RedisTier::stats() const {
  std::lock_guard lock(impl_->stats_mutex);
  return impl_->stats;
}

}  // namespace surfdeform
