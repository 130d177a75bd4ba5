#include "service/answer_cache.hpp"

#include <exception>

#include "service/replies.hpp"

namespace surfdeform {

size_t EstimateBytes(const Reply& r) {
  return sizeof(Reply) + r.body.size() + r.gzip_body.size() + r.content_type.size() +
         (r.stats ? StatsHeaderText(r).size() : 0) + r.etag.size() + 32 * r.timings.size() + 256;
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
  Reply fresh;  // what the making request gets; the cache keeps it marked kept
  auto answer = answers_.GetOrCompute(
      key,
      [&make, &thrown, &fresh]() -> Result<std::shared_ptr<const Reply>> {
        try {
          SURFDEFORM_ASSIGN_OR_RETURN(fresh, make());
          Reply kept_form = fresh;
          MarkKept(&kept_form);
          return std::make_shared<const Reply>(std::move(kept_form));
        } catch (...) {
          thrown = std::current_exception();
          return Status(ErrorCode::kInternal, "making the answer failed");
        }
      },
      &hit);
  if (thrown) std::rethrow_exception(thrown);
  if (!answer.ok()) return answer.status();
  *kept = hit;
  if (!hit) return fresh;
  return **answer;
}

}  // namespace surfdeform
