// Checks on a request's framing, made before its body is read: they close
// the gaps of cpp-httplib 0.11.4 listed in docs/RELIABILITY.md (chunked bodies and
// bodies without a length are read without limit; Content-Length parsed with
// strtoull; compressed bodies inflated past the size limit; header counts
// unbounded).
#pragma once

#include <httplib.h>

#include <optional>

#include "base/status.hpp"

namespace surfdeform::http {

struct Rejection {
  int http_status;
  Status status;
};

inline constexpr size_t kMaxHeaderCount = 100;

// Rejects, in order: more than kMaxHeaderCount headers (431); any
// Transfer-Encoding (411: send a Content-Length); any Content-Encoding other
// than identity (415); several Content-Length headers, or one that is not a
// plain decimal number (400); a POST, PUT or PATCH without Content-Length
// (411); a Content-Length over `max_body_bytes` (413, with the limit and the
// actual value). `body_length` receives the declared length (0 without one;
// the declared value too when it is over the limit).
std::optional<Rejection> CheckFraming(const httplib::Request& request, size_t max_body_bytes,
                                      size_t* body_length);

}  // namespace surfdeform::http
