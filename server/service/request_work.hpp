// The prologue every route that does work shares: the request's clock
// (started when the request's work begins), its admission ticket and the
// threads the ticket allows, the JSON of its parameters, and its mesh
// imported; with the time these took (the "parse" timing).
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

#include "base/status.hpp"
#include "meshio/mesh_import.hpp"
#include "service/admission.hpp"
#include "service/request_clock.hpp"
#include "service/service_limits.hpp"

namespace surfdeform {

class RequestWork {
 public:
  explicit RequestWork(const ServiceLimits& limits);
  RequestWork(const RequestWork&) = delete;
  RequestWork& operator=(const RequestWork&) = delete;

  // A slot from `admission`, waiting at most what is left of the budget
  // (kUnavailable: refused); held until this object ends. Parsing is timed
  // from here, not from the wait.
  Status Admit(Admission& admission, int engine_threads);

  // The request's JSON (`field` names it in errors: "params", "body"),
  // within the service's depth limit, duplicate keys refused.
  Result<nlohmann::json> ParseJson(std::string_view text, const char* field) const;

  // The mesh's bytes imported within the service's limits (kMalformed for
  // none), then EndParse().
  Result<ImportedMesh> Import(std::string_view mesh);

  // Ends the parse phase: its time, then the clock's check.
  Status EndParse();

  const RequestClock& clock() const { return clock_; }
  int threads() const { return threads_; }  // 0 until admitted
  double parse_ms() const { return parse_ms_; }

 private:
  const ServiceLimits& limits_;
  RequestClock clock_;
  std::chrono::steady_clock::time_point parse_start_;
  std::optional<Admission::Ticket> ticket_;
  int threads_ = 0;
  double parse_ms_ = 0.0;
};

}  // namespace surfdeform
