// What a service call returns for the HTTP layer to send: plain bytes and
// strings, no engine types (the HTTP layer must not see Eigen).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace surfdeform {

struct Timing {
  std::string name;  // parse, flatten, deform, encode
  double ms = 0.0;
};

// A reply's statistics for the X-Surfdeform-Stats header: a typed struct
// per route (reply_stats.hpp), written as JSON once, by the HTTP layer
// (StatsHeaderText). Counts, quality, what was reused.
class ReplyStats {
 public:
  virtual ~ReplyStats() = default;
  virtual nlohmann::json ToJson() const = 0;
};

struct Reply {
  std::string body;
  std::string content_type;
  std::vector<Timing> timings;
  // For the X-Surfdeform-Stats header (null: none), checked finite when
  // the reply is made (replies.hpp, CheckedStats).
  std::shared_ptr<const ReplyStats> stats;
  // Served from the kept answers (MarkKept): the header says so.
  bool answer_kept = false;
  std::string etag;  // over the body bytes (deterministic)
  bool cache_hit = false;
  // The body is a function of the URL and the Accept header alone (a content
  // id's): cacheable forever, varying by Accept.
  bool immutable = false;
  std::string surface_id;  // CreateSurface: the id of the flattened surface
  std::string model_id;    // UploadModel: the model's id
  // The request's If-None-Match named `etag`: 304, no body.
  bool not_modified = false;
  // The body gzipped (content_coding.hpp), for a request that accepts it;
  // empty when the answer does not compress or was made without it.
  std::string gzip_body;
};

// The stats header's text: compact JSON, invalid UTF-8 replaced, cut to
// the header's bound (replies.hpp, BoundedStats); empty: no header.
std::string StatsHeaderText(const Reply& reply);

// `stats` as the header writes them: compact JSON, invalid UTF-8 replaced.
inline std::string StatsJsonText(const nlohmann::json& stats) {
  return stats.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace surfdeform
