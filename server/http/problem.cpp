#include "http/problem.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace surfdeform::http {

int HttpStatusOf(ErrorCode code) {
  switch (code) {
    case ErrorCode::kOk:
      return 200;
    case ErrorCode::kMalformed:
      return 400;
    case ErrorCode::kNotFound:
    case ErrorCode::kUnknownModel:
      return 404;
    case ErrorCode::kNotAcceptable:
      return 406;
    case ErrorCode::kLimitExceeded:
    case ErrorCode::kDeadlineExceeded:  // the request asks for more work than the server allows
      return 413;
    case ErrorCode::kUnsupportedFormat:
      return 415;
    case ErrorCode::kInvalidArgument:
    case ErrorCode::kDegenerate:
    case ErrorCode::kNotConverged:
    case ErrorCode::kOutsideSheet:
      return 422;
    case ErrorCode::kUnavailable:
      return 503;
    case ErrorCode::kInternal:
      return 500;
  }
  return 500;
}

const char* StatusTitle(int s) {
  switch (s) {
    case 400:
      return "Bad Request";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 406:
      return "Not Acceptable";
    case 408:
      return "Request Timeout";
    case 411:
      return "Length Required";
    case 413:
      return "Content Too Large";
    case 414:
      return "URI Too Long";
    case 415:
      return "Unsupported Media Type";
    case 416:
      return "Range Not Satisfiable";
    case 422:
      return "Unprocessable Content";
    case 429:
      return "Too Many Requests";
    case 431:
      return "Request Header Fields Too Large";
    case 500:
      return "Internal Server Error";
    case 503:
      return "Service Unavailable";
    default:
      return s >= 500 ? "Server Error" : "Client Error";
  }
}

std::string ProblemJson(const Status& status, int http_status, const std::string& instance,
                        const std::string& request_id) {
  nlohmann::json j;
  j["type"] = "about:blank";
  j["title"] = StatusTitle(http_status);
  j["status"] = http_status;
  j["detail"] = http_status >= 500 && status.code() == ErrorCode::kInternal
                    ? "internal error; the request id identifies it in the server's log"
                    : status.message();
  j["code"] = ErrorCodeName(status.code());
  if (!instance.empty()) j["instance"] = instance;
  if (!request_id.empty()) j["request_id"] = request_id;
  if (!status.field().empty()) j["field"] = status.field();
  if (status.has_limit()) {
    auto number = [](double x) -> nlohmann::json {
      if (std::floor(x) == x && std::abs(x) < 9e15) return static_cast<long long>(x);
      return x;
    };
    j["limit"] = number(status.limit());
    j["actual"] = number(status.actual());
  }
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace surfdeform::http
