// Answers kept: the encoded replies of POST /v1/deform by their
// key (proto/answer_key.hpp), in an LRU bounded by bytes
// (limits.answer_cache_bytes, --answer-cache-mib). A repeated request is
// answered from it with no parse, deformation or encoding; concurrent
// requests for the same answer make it once. A budget of 0 bypasses it
// entirely (not even concurrent requests share), for load tests of the work.
#pragma once

#include <functional>
#include <string>

#include "base/status.hpp"
#include "service/reply.hpp"
#include "service/single_flight_cache.hpp"

namespace surfdeform {

class AnswerCache {
 public:
  explicit AnswerCache(size_t capacity_bytes);

  using Make = std::function<Result<Reply>()>;

  // The answer for `key`: kept (*kept true; its stats say so, MarkKept), or
  // made by `make` now, and kept when it succeeds and fits the budget.
  Result<Reply> GetOrMake(const std::string& key, const Make& make, bool* kept);

  CacheStats stats() const { return answers_.stats(); }

 private:
  const bool enabled_;
  SingleFlightCache<Reply> answers_;
};

// A reply's memory in the cache: its body, headers' text and key, roughly.
size_t EstimateBytes(const Reply& reply);

}  // namespace surfdeform
