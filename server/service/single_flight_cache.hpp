// A thread-safe LRU cache bounded by bytes, with single-flight fills: when N
// callers ask for the same missing key at once, one computes the value and
// the others wait for that result (and share its error, if it fails).
// Values are immutable and shared (shared_ptr<const V>): an evicted value
// stays alive for as long as a request still holds it.
//
// Header-only and free of geometry types so that it can be tested with any
// value type and used from any layer.
#pragma once

#include <cstdint>
#include <exception>
#include <functional>
#include <future>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>

#include "base/status.hpp"

namespace surfdeform {

struct CacheStats {
  uint64_t hits = 0;       // found in the cache
  uint64_t misses = 0;     // not found: computed (once per single flight)
  uint64_t coalesced = 0;  // waited for another caller's computation of the same key
  uint64_t evictions = 0;
  uint64_t failures = 0;  // computations that returned an error (never cached)
  size_t bytes = 0;       // sum of the sizes of the entries held
  size_t entries = 0;
  size_t capacity_bytes = 0;
};

template <class V>
class SingleFlightCache {
 public:
  using Value = std::shared_ptr<const V>;
  using Compute = std::function<Result<Value>()>;
  using SizeOf = std::function<size_t(const V&)>;

  SingleFlightCache(size_t capacity_bytes, SizeOf size_of)
      : capacity_(capacity_bytes), size_of_(std::move(size_of)) {}

  // The cached value, or nullptr (counted as a hit or a miss).
  Value Find(const std::string& key) {
    std::lock_guard lock(mutex_);
    auto it = index_.find(key);
    if (it == index_.end()) {
      ++stats_.misses;
      return nullptr;
    }
    ++stats_.hits;
    lru_.splice(lru_.begin(), lru_, it->second);
    return it->second->value;
  }

  // The cached value, or the result of `compute` run once for all concurrent
  // callers with this key. *hit tells whether this caller was served without
  // computing (from the cache, or by waiting for another caller's result). A
  // value larger than the whole capacity is returned but not kept.
  Result<Value> GetOrCompute(const std::string& key, const Compute& compute, bool* hit) {
    std::unique_lock lock(mutex_);
    if (auto it = index_.find(key); it != index_.end()) {
      ++stats_.hits;
      lru_.splice(lru_.begin(), lru_, it->second);
      *hit = true;
      return it->second->value;
    }
    if (auto it = flights_.find(key); it != flights_.end()) {
      ++stats_.coalesced;
      std::shared_future<Result<Value>> future = it->second;
      lock.unlock();
      *hit = true;
      return future.get();
    }
    ++stats_.misses;
    std::promise<Result<Value>> promise;
    flights_.emplace(key, promise.get_future().share());
    lock.unlock();
    *hit = false;

    Result<Value> result = Status(ErrorCode::kInternal, "the computation did not finish");
    try {
      result = compute();
    } catch (const std::bad_alloc&) {
      result = Status(ErrorCode::kLimitExceeded, "not enough memory for this request");
    } catch (...) {
      result = Status(ErrorCode::kInternal, "internal error");
    }

    lock.lock();
    if (result.ok() && *result != nullptr) {
      Insert(key, *result);
    } else {
      ++stats_.failures;
    }
    flights_.erase(key);
    lock.unlock();
    promise.set_value(result);
    return result;
  }

  // Keeps `value` under `key`, made elsewhere (counted neither a hit nor a
  // miss); a value already there stays and is used again.
  void Put(const std::string& key, const Value& value) {
    if (value == nullptr) return;
    std::lock_guard lock(mutex_);
    if (auto it = index_.find(key); it != index_.end()) {
      lru_.splice(lru_.begin(), lru_, it->second);
      return;
    }
    Insert(key, value);
  }

  CacheStats stats() const {
    std::lock_guard lock(mutex_);
    CacheStats s = stats_;
    s.bytes = bytes_;
    s.entries = index_.size();
    s.capacity_bytes = capacity_;
    return s;
  }

 private:
  struct Entry {
    std::string key;
    Value value;
    size_t bytes;
  };

  void Insert(const std::string& key, const Value& value) {
    const size_t bytes = size_of_(*value);
    if (bytes > capacity_) return;  // would evict everything and still not fit
    lru_.push_front(Entry{key, value, bytes});
    index_[key] = lru_.begin();
    bytes_ += bytes;
    while (bytes_ > capacity_) {
      const Entry& last = lru_.back();
      bytes_ -= last.bytes;
      index_.erase(last.key);
      lru_.pop_back();
      ++stats_.evictions;
    }
  }

  const size_t capacity_;
  const SizeOf size_of_;
  mutable std::mutex mutex_;
  std::list<Entry> lru_;  // most recently used first
  std::unordered_map<std::string, typename std::list<Entry>::iterator> index_;
  std::unordered_map<std::string, std::shared_future<Result<Value>>> flights_;
  size_t bytes_ = 0;
  CacheStats stats_;
};

}  // namespace surfdeform
