// The one place that maps errors to HTTP: a Status becomes a status code and
// an RFC 9457 problem+json body. Messages are the Status's own (written for
// the person who sent the request); internal errors say nothing about the
// server's internals.
#pragma once

#include <string>

#include "base/status.hpp"

namespace surfdeform::http {

inline constexpr const char* kProblemType = "application/problem+json";

// 400 malformed, 404 unknown id, 406 no acceptable format, 413 over a limit,
// 415 unsupported format, 422 valid but unusable, 503 busy, 500 a bug.
int HttpStatusOf(ErrorCode code);

// {"type", "title", "status", "detail", "instance", "request_id", and when
// known "field", "limit", "actual", "code"}.
std::string ProblemJson(const Status& status, int http_status, const std::string& instance,
                        const std::string& request_id);

// The reason phrase for a status code ("Unprocessable Content").
const char* StatusTitle(int http_status);

}  // namespace surfdeform::http
