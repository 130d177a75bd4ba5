#include "http/request_guard.hpp"

#include <algorithm>
#include <iterator>
#include <string>

namespace surfdeform::http {
namespace {

Rejection Reject(int http_status, ErrorCode code, std::string message, std::string field) {
  return Rejection{http_status, Status(code, std::move(message), std::move(field))};
}

bool IsTokenChar(char c) {  // RFC 9110 section 5.6.2
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
         std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
}

// A piece of untrusted text for a message: printable ASCII, at most 40 bytes.
std::string Shown(std::string_view text) {
  std::string out;
  for (char c : text.substr(0, 40)) out += (c >= 0x20 && c < 0x7f) ? c : '?';
  return text.size() > 40 ? out + "..." : out;
}

std::optional<Rejection> CheckRequestLine(std::string_view line) {
  auto bad = [&](const std::string& why) {
    return Reject(400, ErrorCode::kMalformed,
                  "the request line \"" + Shown(line) + "\" " + why +
                      "; it must be METHOD TARGET HTTP/1.1 (RFC 9112 section 3)",
                  "request-line");
  };
  const size_t sp1 = line.find(' ');
  const size_t sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
  if (sp2 == std::string_view::npos || line.find(' ', sp2 + 1) != std::string_view::npos) {
    return bad("does not have three parts separated by single spaces");
  }
  const std::string_view method = line.substr(0, sp1);
  const std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  const std::string_view version = line.substr(sp2 + 1);
  static constexpr std::string_view kMethods[] = {"GET",     "HEAD",    "POST",  "PUT",  "DELETE",
                                                  "CONNECT", "OPTIONS", "TRACE", "PATCH"};
  if (std::find(std::begin(kMethods), std::end(kMethods), method) == std::end(kMethods)) {
    return bad("has an unknown method");
  }
  if (version != "HTTP/1.1" && version != "HTTP/1.0") {
    return bad("is not HTTP/1.1 or HTTP/1.0");
  }
  const bool origin_form = !target.empty() && target.front() == '/';
  const bool absolute_form = target.rfind("http://", 0) == 0 || target.rfind("https://", 0) == 0;
  const bool asterisk_form = target == "*" && method == "OPTIONS";
  if (!origin_form && !absolute_form && !asterisk_form) {
    return bad("has a target that is neither a path nor an absolute http(s) URI");
  }
  for (char c : target) {
    if (static_cast<unsigned char>(c) <= 0x20 || c == 0x7f) {
      return bad("has a control character in its target");
    }
  }
  return std::nullopt;
}

std::optional<Rejection> CheckHeaderLine(std::string_view line) {
  const size_t colon = line.find(':');
  if (line.front() == ' ' || line.front() == '\t') {
    return Reject(400, ErrorCode::kMalformed,
                  "a header field line starts with white space (obsolete line folding, RFC 9112 "
                  "section 5.2): put each field on one line",
                  Shown(line));
  }
  if (colon == std::string_view::npos || colon == 0 ||
      !std::all_of(line.begin(), line.begin() + static_cast<long>(colon), IsTokenChar)) {
    return Reject(400, ErrorCode::kMalformed,
                  "the header field line \"" + Shown(line) +
                      "\" is not NAME: VALUE (a token, a colon with no space before it, a value)",
                  "headers");
  }
  for (char c : line.substr(colon + 1)) {
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f) {
      return Reject(400, ErrorCode::kMalformed,
                    "the header field " + Shown(line.substr(0, colon)) +
                        " has a control character in its value",
                    std::string(line.substr(0, colon)));
    }
  }
  return std::nullopt;
}

}  // namespace

Rejection RequestLineTooLong(size_t length) {
  return Rejection{
      414,
      Status::LimitExceeded(
          "the request line (the method, the target with its query, the version) is over " +
              std::to_string(kMaxRequestLineBytes) +
              " bytes: send long parameters in the body (a multipart \"params\" part)",
          "request-line", static_cast<double>(kMaxRequestLineBytes), static_cast<double>(length))};
}

Rejection TooManyHeaderFields(size_t fields, bool at_least) {
  return Rejection{
      431, Status::LimitExceeded("the request has " + std::string(at_least ? "at least " : "") +
                                     std::to_string(fields) + " header fields; the limit is " +
                                     std::to_string(kMaxHeaderCount),
                                 "headers", kMaxHeaderCount, static_cast<double>(fields))};
}

std::optional<Rejection> CheckHead(std::string_view bytes, size_t head_end) {
  const bool complete = head_end != kHeadIncomplete;
  const std::string_view head = complete ? bytes.substr(0, head_end) : bytes;
  size_t at = 0, fields = 0;
  for (size_t line_number = 0;; ++line_number) {
    const size_t lf = head.find('\n', at);
    const size_t end = lf == std::string_view::npos ? head.size() : lf;
    const bool has_cr = end > at && head[end - 1] == '\r';
    const size_t length = end - at - (has_cr ? 1 : 0);
    const size_t limit = line_number == 0 ? kMaxRequestLineBytes : kMaxHeaderLineBytes;
    if (length > limit) {  // a line so far, or a whole one
      const std::string_view line = head.substr(at, length);
      if (line_number == 0) return RequestLineTooLong(length);
      const std::string name(line.substr(0, std::min<size_t>(line.find(':'), 40)));
      return Rejection{
          431, Status::LimitExceeded(
                   "the header field line " + Shown(name) + " is over " + std::to_string(limit) +
                       " bytes: send long parameters in the body (a multipart "
                       "\"params\" part)",
                   name, static_cast<double>(limit), static_cast<double>(length))};
    }
    if (lf == std::string_view::npos) break;  // the rest is not a whole line yet
    if (!has_cr) {
      return Reject(400, ErrorCode::kMalformed,
                    "a line of the request head ends in a bare LF; HTTP/1.1 lines end in CRLF "
                    "(RFC 9112 section 2.2)",
                    line_number == 0 ? "request-line" : "headers");
    }
    const std::string_view line = head.substr(at, length);
    at = lf + 1;
    if (line_number == 0) {
      if (auto r = CheckRequestLine(line)) return r;
      continue;
    }
    if (line.empty()) break;  // the blank line: the head is over
    if (auto r = CheckHeaderLine(line)) return r;
    ++fields;
  }
  if (fields > kMaxHeaderCount) return TooManyHeaderFields(fields, !complete);
  return std::nullopt;
}

std::optional<Rejection> CheckPath(const std::string& path) {
  for (char c : path) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      return Reject(400, ErrorCode::kMalformed,
                    "the request's path holds a control character (decoded from its %-escapes): "
                    "no resource is named so",
                    "path");
    }
  }
  return std::nullopt;
}

std::optional<Rejection> CheckFraming(const httplib::Request& req, size_t max_body_bytes,
                                      size_t* body_length) {
  *body_length = 0;
  // The client's fields: httplib adds its own to every request it parses.
  const size_t fields = req.headers.size() - std::min(req.headers.size(), kServerAddedHeaders);
  if (fields > kMaxHeaderCount) return TooManyHeaderFields(fields, false);
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
  const bool takes_no_body = req.method == "GET" || req.method == "HEAD" ||
                             req.method == "OPTIONS" || req.method == "TRACE";
  if (length > 0 && takes_no_body) {
    // httplib 0.11.4 does not read a body on these methods: left on the
    // connection, it would be read as the next request.
    return Reject(400, ErrorCode::kMalformed,
                  req.method +
                      " requests take no body; send it without Content-Length or "
                      "Transfer-Encoding",
                  "Content-Length");
  }
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
