// Small pieces of the HTTP edge every request goes through: its id, its
// target, its CPU clock, the headers written from the service's replies.
#pragma once

#include <httplib.h>

#include <string>
#include <vector>

#include "service/reply.hpp"

namespace surfdeform::http {

// "http://host:port/x" -> "/x" (and "http://host" -> "/"); other paths as
// they are (RFC 9112 section 3.2.2's absolute form names the resource by its
// path, as the origin form does).
void StripSchemeAndAuthority(std::string& path);

// The calling thread's CPU time, in seconds: what a request cost its worker,
// whatever else runs on the machine (a load test's check compares refused
// requests with served ones by it, which other tenants do not move).
double ThreadCpuSeconds();

// A client's X-Request-Id is kept when it is 1-64 of [A-Za-z0-9._-].
bool IsSafeRequestId(const std::string& id);
std::string NewRequestId();  // 16 hex digits

// The Server-Timing header's value.
std::string ServerTiming(const std::vector<Timing>& timings);

// A JSON text re-dumped with \u escapes: header values must stay ASCII.
std::string ToAscii(const std::string& json_text);

// Accept-Encoding without its "br" entries (a header with nothing else left
// is dropped: identity). Brotli is never offered: httplib 0.11.4 compresses
// at quality 11, 0.7 s of a worker for a 0.5 MB JSON reply (gzip: 30 ms).
void WithoutBrotli(httplib::Headers* headers);

}  // namespace surfdeform::http
