#include "http/request_guard.hpp"

#include <string>

namespace surfdeform::http {
namespace {

Rejection Reject(int http_status, ErrorCode code, std::string message, std::string field) {
  return Rejection{http_status, Status(code, std::move(message), std::move(field))};
}

}  // namespace

std::optional<Rejection> CheckFraming(const httplib::Request& req, size_t max_body_bytes,
                                      size_t* body_length) {
  *body_length = 0;
  if (req.headers.size() > kMaxHeaderCount) {
    Rejection r{431, Status::LimitExceeded(
                         "the request has " + std::to_string(req.headers.size()) +
                             " header fields; the limit is " + std::to_string(kMaxHeaderCount),
                         "headers", kMaxHeaderCount, static_cast<double>(req.headers.size()))};
    return r;
  }
  if (req.has_header("Transfer-Encoding")) {
    return Reject(411, ErrorCode::kMalformed,
                  "Transfer-Encoding (chunked bodies) is not accepted; send the body with a "
                  "Content-Length",
                  "Transfer-Encoding");
  }
  if (req.has_header("Content-Encoding")) {
    const std::string encoding = req.get_header_value("Content-Encoding");
    if (encoding != "identity" || req.get_header_value_count("Content-Encoding") > 1) {
      return Reject(415, ErrorCode::kUnsupportedFormat,
                    "compressed request bodies (Content-Encoding) are not accepted; send the "
                    "body uncompressed (Draco and GLB are compact already)",
                    "Content-Encoding");
    }
  }
  const size_t lengths = req.get_header_value_count("Content-Length");
  if (lengths > 1) {
    return Reject(400, ErrorCode::kMalformed, "the request has more than one Content-Length",
                  "Content-Length");
  }
  const bool needs_body = req.method == "POST" || req.method == "PUT" || req.method == "PATCH";
  if (lengths == 0) {
    if (needs_body) {
      return Reject(411, ErrorCode::kMalformed,
                    "a " + req.method + " request needs a Content-Length header", "Content-Length");
    }
    return std::nullopt;
  }
  const std::string text = req.get_header_value("Content-Length");
  const bool digits = !text.empty() && text.size() <= 19 &&
                      text.find_first_not_of("0123456789") == std::string::npos;
  if (!digits) {
    return Reject(400, ErrorCode::kMalformed,
                  "Content-Length must be a non-negative decimal number", "Content-Length");
  }
  const unsigned long long length = std::stoull(text);
  *body_length = static_cast<size_t>(length);
  if (length > max_body_bytes) {
    return Rejection{413,
                     Status::LimitExceeded("the request body is " + text + " bytes; the limit is " +
                                               std::to_string(max_body_bytes),
                                           "Content-Length", static_cast<double>(max_body_bytes),
                                           static_cast<double>(length))};
  }
  return std::nullopt;
}

}  // namespace surfdeform::http
