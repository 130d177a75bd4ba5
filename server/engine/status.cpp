#include "engine/status.hpp"

namespace surfdeform {

const char* ErrorCodeName(ErrorCode code) {
  switch (code) {
    case ErrorCode::kOk:
      return "ok";
    case ErrorCode::kInvalidArgument:
      return "invalid_argument";
    case ErrorCode::kDegenerate:
      return "degenerate";
    case ErrorCode::kLimitExceeded:
      return "limit_exceeded";
    case ErrorCode::kDeadlineExceeded:
      return "deadline_exceeded";
    case ErrorCode::kNotConverged:
      return "not_converged";
    case ErrorCode::kOutsideSheet:
      return "outside_sheet";
    case ErrorCode::kUnsupportedFormat:
      return "unsupported_format";
    case ErrorCode::kMalformed:
      return "malformed";
    case ErrorCode::kNotFound:
      return "not_found";
    case ErrorCode::kNotAcceptable:
      return "not_acceptable";
    case ErrorCode::kUnavailable:
      return "unavailable";
    case ErrorCode::kInternal:
      return "internal";
  }
  return "unknown";
}

Status Status::WithFieldPrefix(const std::string& prefix) const {
  if (ok() || prefix.empty()) return *this;
  std::string joined = prefix;
  if (!field_.empty()) {
    if (field_.front() != '[') joined += '.';
    joined += field_;
  }
  Status s = *this;
  s.field_ = joined;
  return s;
}

std::string Status::ToString() const {
  if (ok()) return "ok";
  std::string s = ErrorCodeName(code_);
  if (!field_.empty()) s += " at " + field_;
  s += ": " + message_;
  return s;
}

}  // namespace surfdeform
