#include "service/part_replies.hpp"

#include <chrono>

#include "base/format.hpp"
#include "engine/common/elapsed.hpp"
#include "meshio/mesh_import.hpp"
#include "part/part_body.hpp"
#include "part/solid_report.hpp"
#include "service/memory_budget.hpp"
#include "service/replies.hpp"
#include "service/reply_stats.hpp"

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

BodyOptions BodyOf(const proto::PartRequest& r, const Surface& surface) {
  BodyOptions o;
  o.thickness = r.part.thickness_mm;
  o.side = r.part.side;
  if (r.sampling) {
    o.nu = r.sampling->nu;
    o.nv = r.sampling->nv;
  } else {
    const auto [nu, nv] = BodySamples(surface);
    o.nu = nu;
    o.nv = nv;
  }
  return o;
}

}  // namespace

Status CheckPartSize(const proto::PartRequest& request, const Surface& surface,
                     const ServiceLimits& limits) {
  const BodyOptions o = BodyOf(request, surface);
  const size_t vertices = 2 * static_cast<size_t>(o.nu) * static_cast<size_t>(o.nv);
  if (vertices > limits.max_output_vertices) {
    return Status::LimitExceeded(
        Format("the body would have %zu vertices (2 x %d x %d samples), more than this server "
               "returns (%zu)",
               vertices, o.nu, o.nv, limits.max_output_vertices),
        "sampling", static_cast<double>(limits.max_output_vertices), static_cast<double>(vertices));
  }
  const double triangles = static_cast<double>(BodyTriangles(surface, o));
  return CheckMemory(triangles * kPartBytesPerTriangle, limits.request_memory_bytes, "the part",
                     "sampling");
}

namespace {

// A part made: checked (never sent when a check fails), measured against the
// printer's limits, and its reply.
Result<Reply> FinishPart(const Mesh& part, std::shared_ptr<PartReplyStats> stats,
                         const proto::PartRequest& request, const std::string& field,
                         bool report_json, std::vector<Timing> timings, const RequestClock& clock) {
  const auto t0 = Clock::now();
  stats->solid = CheckSolid(part);
  timings.push_back({"check", MsSince(t0)});
  SURFDEFORM_RETURN_IF_ERROR(clock.Check("part's checks"));
  SURFDEFORM_RETURN_IF_ERROR(
      SolidProblem(stats->solid, field == "body" ? "the part" : "the body", field));
  const PartSettings& p = request.part;
  if (p.min_wall_mm > 0 && !stats->thinnest_wall_mm) {
    stats->warnings.push_back(Format(
        "the walls of an uploaded body are not measured: printer.min_wall_mm %g mm is not checked",
        p.min_wall_mm));
  } else if (p.min_wall_mm > 0 && *stats->thinnest_wall_mm < p.min_wall_mm) {
    const std::string thin =
        Format("the wall is %g mm thick, thinner than the printer's minimum of %g mm",
               *stats->thinnest_wall_mm, p.min_wall_mm);
    if (p.strict) {
      return Status(ErrorCode::kInvalidArgument, thin + " (strict)", "body.thickness_mm")
          .WithLimit(p.min_wall_mm, *stats->thinnest_wall_mm);
    }
    stats->warnings.push_back(thin);
  }
  if (report_json) {
    SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, JsonReply(stats->ToJson()));
    reply.timings = std::move(timings);
    return reply;
  }
  const proto::OutputFormat format = stats->format;
  proto::OutputOptions output = request.output;
  output.format = format;
  ImportedMesh none;
  EncodeContext encode;
  encode.object_name = "part";
  return MeshReply(part, output, format, none, false, std::move(timings), std::move(stats), encode);
}

}  // namespace

Result<Reply> MakePartReply(const proto::PartRequest& request, const Surface& surface,
                            const std::string& surface_id, proto::OutputFormat format,
                            bool report_json, const RequestClock& clock) {
  const auto t0 = Clock::now();
  const BodyOptions body = BodyOf(request, surface);
  SURFDEFORM_ASSIGN_OR_RETURN(Mesh part, ThickenSurface(surface, body));
  SURFDEFORM_RETURN_IF_ERROR(clock.Check("part's body"));
  auto stats = std::make_shared<PartReplyStats>();
  stats->format = format;
  stats->surface_id = surface_id;
  stats->part = request.part;
  stats->nu = body.nu;
  stats->nv = body.nv;
  // The body alone: its every wall is the thickness.
  stats->thinnest_wall_mm = request.part.thickness_mm;
  return FinishPart(part, std::move(stats), request, "body", report_json, {{"body", MsSince(t0)}},
                    clock);
}

Status CheckUploadedPartSize(const Mesh& body, const ServiceLimits& limits) {
  return CheckMemory(static_cast<double>(body.triangles.size()) * kPartBytesPerTriangle,
                     limits.request_memory_bytes, "the part", "body.model_id");
}

Result<Reply> MakeUploadedPartReply(const proto::PartRequest& request, const Mesh& body,
                                    proto::OutputFormat format, bool report_json,
                                    const RequestClock& clock) {
  Mesh part;  // its geometry alone: a part is a solid, not a look
  part.positions = body.positions;
  part.triangles = body.triangles;
  auto stats = std::make_shared<PartReplyStats>();
  stats->format = format;
  stats->model_id = request.body_model_id;
  stats->part = request.part;
  return FinishPart(part, std::move(stats), request, "body.model_id", report_json, {}, clock);
}

}  // namespace surfdeform
