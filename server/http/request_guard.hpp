// Checks on a request's framing, made before its body is read: they close
// the gaps of cpp-httplib 0.11.4 listed in docs/RELIABILITY.md (chunked bodies and
// bodies without a length are read without limit; Content-Length parsed with
// strtoull; compressed bodies inflated past the size limit; header counts
// unbounded).
#pragma once

#include <httplib.h>

#include <optional>
#include <string_view>

#include "base/status.hpp"

namespace surfdeform::http {

struct Rejection {
  int http_status;
  Status status;
};

inline constexpr size_t kMaxHeaderCount = 100;
// cpp-httplib 0.11.4 as Debian compiles it (CPPHTTPLIB_REQUEST_URI_MAX_LENGTH
// and CPPHTTPLIB_HEADER_MAX_LENGTH, 8192 bytes with the line's CRLF): the
// longest request line (the target and its query, `?params=` included) and
// the longest header field line (an X-Surfdeform-Params header included).
inline constexpr size_t kMaxRequestLineBytes = 8190;
inline constexpr size_t kMaxHeaderLineBytes = 8190;
// The header fields cpp-httplib adds to every request it parses
// (REMOTE_ADDR, REMOTE_PORT, LOCAL_ADDR, LOCAL_PORT): not the client's.
inline constexpr size_t kServerAddedHeaders = 4;

// The refusals for a request line over kMaxRequestLineBytes (414; `length`
// as far as it is known) and for more than kMaxHeaderCount fields (431;
// `at_least` when only part of the head was counted). The gate's checks,
// the framing checks and httplib's own refusals answer with these.
Rejection RequestLineTooLong(size_t length);
Rejection TooManyHeaderFields(size_t fields, bool at_least);

// Checks a request head as it arrives (`bytes`: the head so far, or all of
// it and more when `complete`; `head_end` then is where its blank line
// ends), before httplib parses it, so that a request that cannot be framed
// is answered at once and its connection closed (RFC 9112): a line that
// ends in a bare LF (section 2.2; 400), a request line over
// kMaxRequestLineBytes (414), one that is not "METHOD target HTTP/1.x"
// with a method and a target form httplib serves (400), a header line over
// kMaxHeaderLineBytes (431), one that is not "name: value" or folds onto
// the next (section 5.2; 400), more than kMaxHeaderCount fields (431).
// Incomplete heads are refused as soon as the bytes so far break a rule.
std::optional<Rejection> CheckHead(std::string_view bytes, size_t head_end);
inline constexpr size_t kHeadIncomplete = static_cast<size_t>(-1);

// Rejects, in order: more than kMaxHeaderCount headers (431); any
// Transfer-Encoding (411: send a Content-Length); any Content-Encoding other
// than identity (415); several Content-Length headers, or one that is not a
// plain decimal number (400); a POST, PUT or PATCH without Content-Length
// (411); a body declared on GET, HEAD, OPTIONS or TRACE (400: httplib
// would read it as the next request); a Content-Length over
// `max_body_bytes` (413, with the limit and the actual value). `body_length` receives the declared
// length (0 without one; the declared value too when it is over the limit). Rejects a path that,
// decoded, holds a control character (a NUL or any byte below 0x20, or DEL: 400):
// "/index.html%00.js" would read one file and name another's type.
std::optional<Rejection> CheckPath(const std::string& decoded_path);

std::optional<Rejection> CheckFraming(const httplib::Request& request, size_t max_body_bytes,
                                      size_t* body_length);

}  // namespace surfdeform::http
