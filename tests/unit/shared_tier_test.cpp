// The second level of the surface cache against a real redis-server: two
// Services stand for two replicas. Sharing by id and by content, one
// flattening across replicas, and Redis down, slow, full or lying: every
// request still succeeds.
#include "service/shared_tier.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "service/service.hpp"
#include "service/sheet_codec.hpp"
#include "support/redis_process.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

const char kCylinder[] =
    R"({"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},"sampling":{"nu":8,"nv":8}})";

std::string Wave(int n) {
  return R"({"surface":{"kind":"wave"},"sampling":{"nu":)" + std::to_string(n) + R"(,"nv":)" +
         std::to_string(n) + "}}";
}

std::shared_ptr<SharedTier> Tier(const std::string& url, std::vector<std::string>* log = nullptr,
                                 double wait_ms = 10000, double breaker_open_ms = 300) {
  SharedTierOptions o;
  o.url = url;
  o.timeout_ms = 200;
  o.wait_ms = wait_ms;
  o.lock_ms = 130000;
  o.breaker_open_ms = breaker_open_ms;
  auto tier = SharedTier::Create(o, [log](const std::string& state, const std::string& detail) {
    if (log != nullptr) log->push_back(state + ": " + detail);
  });
  EXPECT_TRUE(tier.ok()) << tier.status().ToString();
  return tier.ok() ? std::shared_ptr<SharedTier>(std::move(*tier)) : nullptr;
}

ServiceOptions Replica(std::shared_ptr<SharedTier> tier) {
  ServiceOptions o;
  o.shared_tier = std::move(tier);
  // Room for the sanitizer build, ~15x slower.
  o.limits.flatten_time_budget_ms = o.limits.request_time_budget_ms = 120000;
  return o;
}

std::string IdOf(const Result<Reply>& r) { return json::parse(r->body).at("id"); }

TEST(SharedTierUrl, BadUrlsAreRefusedWithTheReason) {
  for (const char* url : {"http://localhost", "redis://", "redis://host:0", "redis://host:99999",
                          "redis://host/x", "unix://relative", "redis://[::1"}) {
    SharedTierOptions o;
    o.url = url;
    auto tier = SharedTier::Create(o, nullptr);
    ASSERT_FALSE(tier.ok()) << url;
    EXPECT_NE(tier.status().message().find(url), std::string::npos) << tier.status().message();
  }
  SharedTierOptions o;
  o.url = "redis://:secret@[::1]:6380/2";
  EXPECT_TRUE(SharedTier::Create(o, nullptr).ok());
}

TEST(SharedTier, ASurfaceFlattenedOnOneReplicaIsServedByIdOnAnother) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0) << "redis-server did not start (scripts/setup.sh installs it)";
  Service a(Replica(Tier(redis.url())));
  Service b(Replica(Tier(redis.url())));
  auto created = a.CreateSurface(kCylinder);
  ASSERT_TRUE(created.ok()) << created.status().ToString();
  const std::string id = IdOf(created);
  EXPECT_EQ(a.shared_tier_stats().writes, 1u);
  EXPECT_EQ(redis.Command({"EXISTS", SheetKey(id)}), "1");
  const std::string ttl = redis.Command({"TTL", SheetKey(id)});
  EXPECT_GT(std::stoll(ttl), 86400) << ttl;

  // By id on B: the same sheet, byte for byte.
  auto sheet_b = b.GetSurface(id);
  ASSERT_TRUE(sheet_b.ok()) << sheet_b.status().ToString();
  auto sheet_a = a.GetSurface(id);
  EXPECT_EQ(json::parse(sheet_b->body).at("flat"), json::parse(sheet_a->body).at("flat"));
  EXPECT_EQ(json::parse(sheet_b->body).at("request"), json::parse(sheet_a->body).at("request"));
  EXPECT_EQ(b.shared_tier_stats().hits, 1u);
  // Now in B's first level: no second read.
  ASSERT_TRUE(b.GetSurface(id).ok());
  EXPECT_EQ(b.shared_tier_stats().hits, 1u);

  // A deformation by id on a third replica gives A's bytes.
  Service c(Replica(Tier(redis.url())));
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string params = R"({"surface_id":")" + id + R"(","output":{"format":"obj"}})";
  auto on_a = a.Deform({obj, params, ""});
  auto on_c = c.Deform({obj, params, ""});
  ASSERT_TRUE(on_a.ok() && on_c.ok()) << on_c.status().ToString();
  EXPECT_EQ(on_a->body, on_c->body);

  // By content on B: no flattening (a hit, with A's flattening time).
  auto again = b.CreateSurface(kCylinder);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(again->cache_hit);
}

TEST(SharedTier, ReplicasAskedForTheSameNewSurfaceFlattenItOnce) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0);
  constexpr int kReplicas = 3;
  std::vector<std::unique_ptr<Service>> replicas;
  for (int k = 0; k < kReplicas; ++k) {
    replicas.push_back(std::make_unique<Service>(Replica(Tier(redis.url()))));
  }
  // The paper's descent on a 28 x 28 wave: long enough (~0.2 s) that all
  // replicas ask while the first one flattens.
  const std::string body =
      R"({"surface":{"kind":"wave"},"sampling":{"nu":28,"nv":28},"flatten":{"method":"paper"}})";
  std::vector<int> ok(kReplicas, 0), flattened(kReplicas, 0);
  std::atomic<bool> go{false};
  std::vector<std::thread> threads;
  for (int k = 0; k < kReplicas; ++k) {
    threads.emplace_back([&, k] {
      while (!go) std::this_thread::yield();
      if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the lock is taken
      auto r = replicas[k]->CreateSurface(body);
      ok[k] = r.ok();
      flattened[k] = r.ok() && !r->cache_hit;
    });
  }
  go = true;
  for (auto& t : threads) t.join();
  uint64_t locks = 0, waits = 0, wait_hits = 0;
  int flattenings = 0;
  for (int k = 0; k < kReplicas; ++k) {
    EXPECT_TRUE(ok[k]) << "replica " << k;
    flattenings += flattened[k];
    const SharedTierStats s = replicas[k]->shared_tier_stats();
    locks += s.locks_acquired;
    waits += s.lock_waits;
    wait_hits += s.lock_wait_hits;
  }
  EXPECT_EQ(flattenings, 1);
  EXPECT_EQ(locks, 1u);
  EXPECT_EQ(waits, kReplicas - 1u);
  EXPECT_EQ(wait_hits, kReplicas - 1u);
  EXPECT_EQ(redis.Command({"EXISTS", SheetLockKey(IdOf(replicas[0]->CreateSurface(body)))}), "0");
}

TEST(SharedTier, AReplicaHoldingTheLockThatNeverFinishesDelaysOthersOnlyByTheWaitBound) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0);
  Service probe({});
  const std::string id = IdOf(probe.CreateSurface(kCylinder));
  // A replica took the lock, then died.
  ASSERT_EQ(redis.Command({"SET", SheetLockKey(id), "dead", "PX", "60000"}), "OK");
  Service b(Replica(Tier(redis.url(), nullptr, /*wait_ms=*/300)));
  const auto t0 = Clock::now();
  auto r = b.CreateSurface(kCylinder);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_FALSE(r->cache_hit);  // flattened here
  EXPECT_GE(ms, 250);
  EXPECT_LT(ms, 5000);
  EXPECT_EQ(b.shared_tier_stats().lock_waits, 1u);
  EXPECT_EQ(b.shared_tier_stats().lock_wait_hits, 0u);
}

TEST(SharedTier, CorruptTruncatedOrForeignValuesAreIgnoredAndCounted) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0);
  Service a(Replica(Tier(redis.url())));
  const std::string id = IdOf(a.CreateSurface(kCylinder));
  const std::string good = redis.Command({"GET", SheetKey(id)});
  ASSERT_GT(good.size(), 100u);
  // The value of another surface under this id: checksummed, but it answers
  // another request.
  const std::string other_id = IdOf(a.CreateSurface(Wave(6)));
  const std::string other = redis.Command({"GET", SheetKey(other_id)});

  int k = 0;
  for (const std::string& bad :
       {std::string("garbage"), good.substr(0, good.size() / 2), good.substr(0, good.size() - 1),
        std::string(good).replace(40, 1, "X"), other}) {
    ASSERT_EQ(redis.Command({"SET", SheetKey(id), bad}), "OK");
    Service b(Replica(Tier(redis.url())));
    auto by_id = b.GetSurface(id);
    ASSERT_FALSE(by_id.ok()) << "value " << k;
    EXPECT_EQ(by_id.status().code(), ErrorCode::kNotFound);
    EXPECT_EQ(b.shared_tier_stats().corrupt, 1u) << "value " << k;
    // By content: flattened here, and the good value written back.
    auto created = b.CreateSurface(kCylinder);
    ASSERT_TRUE(created.ok()) << created.status().ToString();
    EXPECT_FALSE(created->cache_hit);
    // (Compared decoded: the value carries its own flattening time.)
    const std::string written = redis.Command({"GET", SheetKey(id)});
    EXPECT_TRUE(written != bad && DecodeSheet(written, 256).ok()) << "value " << k;
    ++k;
  }
}

TEST(SharedTier, RedisDownEveryRequestSucceedsAndTheBreakerStopsTrying) {
  std::vector<std::string> log;
  // Nothing listens on this port. The breaker stays open for the whole test
  // (no probe, however slow the build).
  Service a(Replica(Tier("redis://127.0.0.1:" + std::to_string(testing::FreePort()), &log, 10000,
                         /*breaker_open_ms=*/600000)));
  for (int n = 4; n < 14; ++n) {
    auto r = a.CreateSurface(Wave(n));
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_FALSE(r->cache_hit);
  }
  const SharedTierStats s = a.shared_tier_stats();
  EXPECT_EQ(s.errors, 3u);  // then the breaker opened
  EXPECT_GT(s.skipped, 10u);
  EXPECT_TRUE(s.breaker_open);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("down: connecting to Redis"), std::string::npos) << log[0];
}

TEST(SharedTier, RedisKilledAndRestartedSharingResumes) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0);
  std::vector<std::string> log;
  Service a(Replica(Tier(redis.url(), &log)));
  ASSERT_TRUE(a.CreateSurface(Wave(5)).ok());
  redis.Kill();
  for (int n = 6; n < 12; ++n) ASSERT_TRUE(a.CreateSurface(Wave(n)).ok());
  EXPECT_TRUE(a.shared_tier_stats().breaker_open);
  ASSERT_TRUE(redis.Start());
  std::this_thread::sleep_for(std::chrono::milliseconds(400));  // the breaker's cool-down
  auto r = a.CreateSurface(Wave(12));
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(a.shared_tier_stats().breaker_open);
  const std::string id = IdOf(r);
  Service b(Replica(Tier(redis.url())));
  EXPECT_TRUE(b.GetSurface(id).ok());
  EXPECT_EQ(log, (std::vector<std::string>{"down: connecting to Redis: Connection refused",
                                           "up: commands succeed again"}));
}

TEST(SharedTier, ASlowRedisCostsARequestOnlyTheTimeout) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0);
  Service a(Replica(Tier(redis.url())));
  std::string slept;
  std::thread sleeper([&] { slept = redis.Command({"DEBUG", "SLEEP", "2"}); });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto t0 = Clock::now();
  auto r = a.CreateSurface(kCylinder);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  sleeper.join();
  ASSERT_EQ(slept, "OK");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  // Get, lock and put time out at 200 ms each, at most (one connection each).
  EXPECT_LT(ms, 1500);
  EXPECT_GE(a.shared_tier_stats().errors, 1u);
}

TEST(SharedTier, AFullRedisRefusesWritesAndRequestsStillSucceed) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0);
  ASSERT_EQ(redis.Command({"CONFIG", "SET", "maxmemory-policy", "noeviction"}), "OK");
  ASSERT_EQ(redis.Command({"CONFIG", "SET", "maxmemory", "1"}), "OK");
  Service a(Replica(Tier(redis.url())));
  auto r = a.CreateSurface(Wave(20));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(a.shared_tier_stats().writes, 0u);
  EXPECT_GE(a.shared_tier_stats().errors, 1u);  // OOM
  EXPECT_EQ(redis.Command({"DBSIZE"}), "0");
}

}  // namespace
}  // namespace surfdeform
