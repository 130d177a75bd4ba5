#include "service/request_work.hpp"

#include "base/fault_points.hpp"
#include "engine/elapsed.hpp"
#include "proto/json_object.hpp"
#include "service/limit_checks.hpp"

namespace surfdeform {

RequestWork::RequestWork(const ServiceLimits& limits)
    : limits_(limits),
      clock_(limits.request_time_budget_ms),
      parse_start_(std::chrono::steady_clock::now()) {}

Status RequestWork::Admit(Admission& admission, int engine_threads) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto ticket, admission.Enter(clock_.remaining_ms()));
  threads_ = ThreadsFor(ticket, engine_threads);
  ticket_.emplace(std::move(ticket));
  parse_start_ = std::chrono::steady_clock::now();
  return Status::Ok();
}

Result<nlohmann::json> RequestWork::ParseJson(std::string_view text, const char* field) const {
  return proto::ParseRequestJson(text, limits_.max_json_depth, field);
}

Result<ImportedMesh> RequestWork::Import(std::string_view mesh) {
  if (mesh.empty()) {
    return Status(ErrorCode::kMalformed,
                  "the request carries no mesh: send the mesh file, or name an uploaded one "
                  "(POST /v1/models) by \"model_id\" in the parameters",
                  "mesh");
  }
  faults::MaybeFailAllocation();  // the test build's fault point; nothing in production
  SURFDEFORM_ASSIGN_OR_RETURN(auto imported, ImportMesh(mesh, ImportLimitsOf(limits_)));
  SURFDEFORM_RETURN_IF_ERROR(EndParse());
  return imported;
}

Status RequestWork::EndParse() {
  parse_ms_ = MsSince(parse_start_);
  return clock_.Check("parsing");
}

}  // namespace surfdeform
