// The error vocabulary every layer of surfdeform shares.
//
// Functions never throw and never assert on user input: they return a Status
// (or a Result<T> holding either a value or a Status). The code tells the
// caller what kind of failure it is; the message is written for the person who
// sent the input; `field` names the offending input field as a JSON-like path
// ("control_points[3]") when there is one. server/http/problem.cpp maps codes
// to HTTP in one place; no caller decides anything from a message's text.
//
// The codes are grouped by the layer that raises them. The geometry engine
// (server/engine) raises only the first group; a test
// (tests/architecture/engine_boundaries.sh) keeps it so.
#pragma once

#include <string>
#include <utility>
#include <variant>

#include "base/enum_table.hpp"

namespace surfdeform {

enum class ErrorCode {
  kOk = 0,
  // The geometry engine's (and any layer's):
  kInvalidArgument,   // malformed or out-of-range input (a NaN, a count that does not match)
  kDegenerate,        // well-formed but geometrically unusable (zero radius, vanishing normal)
  kLimitExceeded,     // input larger than a published limit
  kDeadlineExceeded,  // a time budget ran out (the limit and the time spent, ms, attached)
  kNotConverged,      // a solver did not reach a usable result (e.g. folded cells remain)
  kOutsideSheet,      // a model's footprint leaves the flat sheet
  kInternal,          // a bug: never caused by input
  // Outside the engine: mesh formats (meshio), requests (proto, http), the service:
  kUnsupportedFormat,  // bytes in no format the reader knows (or one it refuses)
  kMalformed,          // a request that cannot be parsed (syntax, wrong types, unknown fields)
  kNotFound,           // an id that names nothing (e.g. a surface no longer cached)
  kUnknownModel,       // a model id the service does not hold (never uploaded, or evicted)
  kNotAcceptable,      // no output format the caller accepts
  kUnavailable,        // overloaded or shutting down: retry later
};

// The codes' names as problem+json's "code" spells them.
inline constexpr EnumEntry<ErrorCode> kErrorCodes[] = {
    {ErrorCode::kOk, "ok", "no error"},
    {ErrorCode::kInvalidArgument, "invalid_argument", "malformed or out-of-range input"},
    {ErrorCode::kDegenerate, "degenerate", "well-formed but geometrically unusable"},
    {ErrorCode::kLimitExceeded, "limit_exceeded", "input larger than a published limit"},
    {ErrorCode::kDeadlineExceeded, "deadline_exceeded", "a time budget ran out"},
    {ErrorCode::kNotConverged, "not_converged", "a solver did not reach a usable result"},
    {ErrorCode::kOutsideSheet, "outside_sheet", "the model's footprint leaves the flat sheet"},
    {ErrorCode::kInternal, "internal", "a bug: never caused by input"},
    {ErrorCode::kUnsupportedFormat, "unsupported_format", "bytes in no format the reader knows"},
    {ErrorCode::kMalformed, "malformed", "a request that cannot be parsed"},
    {ErrorCode::kNotFound, "not_found", "an id that names nothing"},
    {ErrorCode::kUnknownModel, "unknown_model",
     "a model id the service does not hold: upload the model again"},
    {ErrorCode::kNotAcceptable, "not_acceptable", "no output format the caller accepts"},
    {ErrorCode::kUnavailable, "unavailable", "overloaded or shutting down: retry later"},
};
const char* ErrorCodeName(ErrorCode code);  // from kErrorCodes

class Status {
 public:
  Status() = default;
  Status(ErrorCode code, std::string message, std::string field = {})
      : code_(code), message_(std::move(message)), field_(std::move(field)) {}

  static Status Ok() { return Status(); }

  // kLimitExceeded with the published limit and the actual value, so that a
  // caller can report both as numbers (e.g. in an HTTP problem response).
  static Status LimitExceeded(std::string message, std::string field, double limit, double actual) {
    return Status(ErrorCode::kLimitExceeded, std::move(message), std::move(field))
        .WithLimit(limit, actual);
  }
  // kDeadlineExceeded with the time budget and the time spent, both in ms.
  static Status DeadlineExceeded(std::string message, std::string field, double budget_ms,
                                 double spent_ms) {
    return Status(ErrorCode::kDeadlineExceeded, std::move(message), std::move(field))
        .WithLimit(budget_ms, spent_ms);
  }
  // A copy that also carries the limit that was hit and the actual value.
  Status WithLimit(double limit, double actual) const {
    Status s = *this;
    s.has_limit_ = true;
    s.limit_ = limit;
    s.actual_ = actual;
    return s;
  }

  bool ok() const { return code_ == ErrorCode::kOk; }
  ErrorCode code() const { return code_; }
  const std::string& message() const { return message_; }
  const std::string& field() const { return field_; }
  bool has_limit() const { return has_limit_; }
  double limit() const { return limit_; }
  double actual() const { return actual_; }

  // Prefixes the field path, so that a nested builder can report
  // "surface.control_points[3]" while the inner check only knows "control_points[3]".
  Status WithFieldPrefix(const std::string& prefix) const;

  std::string ToString() const;

 private:
  ErrorCode code_ = ErrorCode::kOk;
  std::string message_;
  std::string field_;
  bool has_limit_ = false;
  double limit_ = 0.0;
  double actual_ = 0.0;
};

inline Status InvalidArgument(std::string message, std::string field = {}) {
  return Status(ErrorCode::kInvalidArgument, std::move(message), std::move(field));
}
inline Status Degenerate(std::string message, std::string field = {}) {
  return Status(ErrorCode::kDegenerate, std::move(message), std::move(field));
}

// A slot for a result still to be computed (a vector filled by threads):
// not ok, and an internal error if it were ever read unfilled.
inline Status NotComputed() { return Status(ErrorCode::kInternal, "not computed"); }

// Either a T or a non-ok Status (an ok Status without a value is taken as
// NotComputed(): "not ok, but the status is OK" cannot be built).
template <typename T>
class Result {
 public:
  Result(T value) : data_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  Result(Status status)                         // NOLINT(google-explicit-constructor)
      : data_(status.ok() ? NotComputed() : std::move(status)) {}

  bool ok() const { return std::holds_alternative<T>(data_); }
  const Status& status() const {
    static const Status kOkStatus;
    return ok() ? kOkStatus : std::get<Status>(data_);
  }
  T& value() & { return std::get<T>(data_); }
  const T& value() const& { return std::get<T>(data_); }
  T&& value() && { return std::get<T>(std::move(data_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::variant<T, Status> data_;
};

}  // namespace surfdeform

// `lhs = value of expr` (a Result<T>), or return its status from the
// enclosing function: SURFDEFORM_ASSIGN_OR_RETURN(auto mesh, ImportMesh(...));
#define SURFDEFORM_ASSIGN_OR_RETURN(lhs, expr) \
  SURFDEFORM_ASSIGN_OR_RETURN_IMPL_(SURFDEFORM_CONCAT_(result_, __LINE__), lhs, expr)
#define SURFDEFORM_CONCAT_INNER_(a, b) a##b
#define SURFDEFORM_CONCAT_(a, b) SURFDEFORM_CONCAT_INNER_(a, b)
#define SURFDEFORM_ASSIGN_OR_RETURN_IMPL_(tmp, lhs, expr) \
  auto tmp = (expr);                                      \
  if (!tmp.ok()) return tmp.status();                     \
  lhs = std::move(tmp).value()

#define SURFDEFORM_RETURN_IF_ERROR(expr)   \
  do {                                     \
    ::surfdeform::Status status_ = (expr); \
    if (!status_.ok()) return status_;     \
  } while (false)
