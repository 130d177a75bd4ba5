#include "service/answer_cache.hpp"

#include <exception>

namespace surfdeform {

size_t EstimateBytes(const Reply& r) {
  return sizeof(Reply) + r.body.size() + r.gzip_body.size() + r.content_type.size() +
         r.stats_json.size() + r.etag.size() + 32 * r.timings.size() + 256;
}

AnswerCache::AnswerCache(size_t capacity_bytes)
    : enabled_(capacity_bytes > 0),
      answers_(capacity_bytes, [](const Reply& r) { return EstimateBytes(r); }) {}

Result<Reply> AnswerCache::GetOrMake(const std::string& key, const Make& make, bool* kept) {
  *kept = false;
  if (!enabled_) return make();
  bool hit = false;
  // An exception from the making (std::bad_alloc) goes on to the caller as
  // it would without the cache (the HTTP layer's opaque 500); callers that
  // waited for it get an internal error.
  std::exception_ptr thrown;
  auto answer = answers_.GetOrCompute(
      key,
      [&make, &thrown]() -> Result<std::shared_ptr<const Reply>> {
        try {
          SURFDEFORM_ASSIGN_OR_RETURN(Reply made, make());
          return std::make_shared<const Reply>(std::move(made));
        } catch (...) {
          thrown = std::current_exception();
          return Status(ErrorCode::kInternal, "making the answer failed");
        }
      },
      &hit);
  if (thrown) std::rethrow_exception(thrown);
  if (!answer.ok()) return answer.status();
  *kept = hit;
  return **answer;
}

}  // namespace surfdeform
