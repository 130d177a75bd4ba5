#include "base/status.hpp"

namespace surfdeform {

const char* ErrorCodeName(ErrorCode code) {
  const std::string_view name = NameOf<ErrorCode>(kErrorCodes, code);
  return name.empty() ? "unknown" : name.data();  // the table's literals end in NUL
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
