// The single-flight LRU: byte bound, LRU order, single flight, no torn entries.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <thread>

#include "service/single_flight_cache.hpp"

namespace surfdeform {
namespace {

struct Blob {
  std::string key;
  size_t bytes;
  std::vector<int> payload;  // filled with a key-derived pattern
};

using Cache = SingleFlightCache<Blob>;

Cache MakeCache(size_t capacity) {
  return Cache(capacity, [](const Blob& b) { return b.bytes; });
}

Cache::Compute Make(const std::string& key, size_t bytes, std::atomic<int>* computed = nullptr) {
  return [=]() -> Result<Cache::Value> {
    if (computed != nullptr) computed->fetch_add(1);
    auto b = std::make_shared<Blob>();
    b->key = key;
    b->bytes = bytes;
    b->payload.assign(64, static_cast<int>(std::hash<std::string>{}(key)));
    return Cache::Value(std::move(b));
  };
}

TEST(SingleFlightCache, StaysWithinItsByteBudgetAndEvictsLeastRecentlyUsed) {
  Cache cache = MakeCache(1000);
  bool hit = false;
  for (const char* k : {"a", "b", "c"}) ASSERT_TRUE(cache.GetOrCompute(k, Make(k, 300), &hit).ok());
  EXPECT_EQ(cache.stats().bytes, 900u);
  ASSERT_NE(cache.Find("a"), nullptr);  // a is now the most recent: b is the least
  ASSERT_TRUE(cache.GetOrCompute("d", Make("d", 300), &hit).ok());
  const CacheStats s = cache.stats();
  EXPECT_LE(s.bytes, 1000u);
  EXPECT_EQ(s.entries, 3u);
  EXPECT_EQ(s.evictions, 1u);
  EXPECT_EQ(cache.Find("b"), nullptr);
  EXPECT_NE(cache.Find("a"), nullptr);
  EXPECT_NE(cache.Find("c"), nullptr);
  EXPECT_NE(cache.Find("d"), nullptr);
  // Larger than the whole budget: returned, not kept, nothing evicted for it.
  auto big = cache.GetOrCompute("big", Make("big", 5000), &hit);
  ASSERT_TRUE(big.ok());
  EXPECT_EQ((*big)->bytes, 5000u);
  EXPECT_EQ(cache.Find("big"), nullptr);
  EXPECT_EQ(cache.stats().entries, 3u);
}

TEST(SingleFlightCache, HitsAndMissesAreCounted) {
  Cache cache = MakeCache(1000);
  bool hit = true;
  ASSERT_TRUE(cache.GetOrCompute("a", Make("a", 10), &hit).ok());
  EXPECT_FALSE(hit);
  ASSERT_TRUE(cache.GetOrCompute("a", Make("a", 10), &hit).ok());
  EXPECT_TRUE(hit);
  EXPECT_EQ(cache.stats().hits, 1u);
  EXPECT_EQ(cache.stats().misses, 1u);
}

TEST(SingleFlightCache, ErrorsAreSharedButNotCached) {
  Cache cache = MakeCache(1000);
  int calls = 0;
  auto failing = [&]() -> Result<Cache::Value> {
    ++calls;
    return Degenerate("zero radius", "surface.radius");
  };
  bool hit;
  auto r = cache.GetOrCompute("x", failing, &hit);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().field(), "surface.radius");
  r = cache.GetOrCompute("x", failing, &hit);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(cache.stats().failures, 2u);
  EXPECT_EQ(cache.stats().entries, 0u);
  // A computation that throws becomes an error for everyone, not a hang.
  r = cache.GetOrCompute(
      "y", []() -> Result<Cache::Value> { throw std::runtime_error("boom"); }, &hit);
  EXPECT_EQ(r.status().code(), ErrorCode::kInternal);
}

TEST(SingleFlightCache, ConcurrentRequestsForOneKeyComputeOnce) {
  Cache cache = MakeCache(1 << 20);
  std::atomic<int> computed{0};
  std::atomic<bool> go{false};
  auto slow = [&]() -> Result<Cache::Value> {
    computed.fetch_add(1);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    auto b = std::make_shared<Blob>();
    b->key = "k";
    b->bytes = 100;
    return Cache::Value(std::move(b));
  };
  constexpr int kThreads = 50;
  std::vector<const Blob*> seen(kThreads, nullptr);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      while (!go.load()) std::this_thread::yield();
      bool hit;
      auto r = cache.GetOrCompute("k", slow, &hit);
      if (r.ok()) seen[t] = r->get();
    });
  }
  go = true;
  for (auto& t : threads) t.join();
  EXPECT_EQ(computed.load(), 1);
  for (const Blob* b : seen) EXPECT_EQ(b, seen[0]);  // one shared value
  const CacheStats s = cache.stats();
  EXPECT_EQ(s.misses, 1u);
  EXPECT_EQ(s.hits + s.coalesced, static_cast<uint64_t>(kThreads - 1));
}

TEST(SingleFlightCache, HammerKeepsEntriesWholeAndTheBoundHeld) {
  Cache cache = MakeCache(20 * 100);  // room for 20 of the 60 keys
  std::atomic<int> torn{0};
  std::atomic<bool> over_budget{false};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      std::mt19937 rng(t);
      for (int k = 0; k < 3000; ++k) {
        const std::string key = "key" + std::to_string(rng() % 60);
        bool hit;
        auto r = cache.GetOrCompute(key, Make(key, 100), &hit);
        if (!r.ok() || (*r)->key != key ||
            (*r)->payload !=
                std::vector<int>(64, static_cast<int>(std::hash<std::string>{}(key)))) {
          torn.fetch_add(1);
        }
        if (cache.stats().bytes > 2000) over_budget = true;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(torn.load(), 0);
  EXPECT_FALSE(over_budget.load());
  const CacheStats s = cache.stats();
  EXPECT_EQ(s.hits + s.misses + s.coalesced, 8u * 3000u);
  EXPECT_GT(s.evictions, 0u);
  EXPECT_EQ(s.entries * 100, s.bytes);
}

}  // namespace
}  // namespace surfdeform
