#include "service/request_work.hpp"

#include "base/fault_points.hpp"
#include "engine/common/elapsed.hpp"
#include "json/bounded_json.hpp"
#include "service/allocator_tuning.hpp"
#include "service/limit_checks.hpp"

namespace surfdeform {

RequestWork::RequestWork(const ServiceLimits& limits, const CancelFlag* cancel,
                         ParseMemory* parse_memory)
    : limits_(limits),
      clock_(limits.request_time_budget_ms, cancel),
      parse_memory_(parse_memory),
      parse_start_(std::chrono::steady_clock::now()) {}

RequestWork::~RequestWork() {
  if (parse_memory_ != nullptr) parse_memory_->Give(parse_values_held_);
  // Some 100 bytes a value at most: a document of this many took far more
  // than a request's usual few megabytes.
  if (parse_values_held_ * 100 >= kLargeRequestBytes) MarkLargeRequest();
}

Status RequestWork::Admit(Admission& admission, int engine_threads) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto ticket, admission.Enter(clock_.remaining_ms()));
  threads_ = ThreadsFor(ticket, engine_threads);
  ticket_.emplace(std::move(ticket));
  parse_start_ = std::chrono::steady_clock::now();
  return Status::Ok();
}

Result<nlohmann::json> RequestWork::ParseJson(std::string_view text, const char* field) {
  // Checked every few thousand values (kJsonCheckpointValues): the time
  // budget, the cancellation, and the document's share of the total.
  return ParseBoundedJson(text, JsonLimitsOf(limits_), field, [this, field]() -> Status {
    SURFDEFORM_RETURN_IF_ERROR(clock_.Check("parsing"));
    if (parse_memory_ == nullptr) return Status::Ok();
    if (!parse_memory_->Take(kJsonCheckpointValues)) {
      return Status(ErrorCode::kUnavailable,
                    std::string("the server holds as many request JSON values as it may (") +
                        std::to_string(parse_memory_->max()) + ") while reading this request's " +
                        field + "; retry later, or send large point sets as a mesh file")
          .WithLimit(static_cast<double>(parse_memory_->max()),
                     static_cast<double>(parse_memory_->held() + kJsonCheckpointValues));
    }
    parse_values_held_ += kJsonCheckpointValues;
    return Status::Ok();
  });
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
