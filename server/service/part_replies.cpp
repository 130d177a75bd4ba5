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

Result<Reply> MakePartReply(const proto::PartRequest& request, const Surface& surface,
                            const std::string& surface_id, proto::OutputFormat format,
                            bool report_json) {
  const auto t0 = Clock::now();
  const BodyOptions body = BodyOf(request, surface);
  SURFDEFORM_ASSIGN_OR_RETURN(Mesh part, ThickenSurface(surface, body));
  const double body_ms = MsSince(t0);
  const auto t1 = Clock::now();
  auto stats = std::make_shared<PartReplyStats>();
  stats->format = format;
  stats->surface_id = surface_id;
  stats->part = request.part;
  stats->nu = body.nu;
  stats->nv = body.nv;
  stats->solid = CheckSolid(part);
  const double check_ms = MsSince(t1);
  // A part that fails a check is never sent as a success.
  SURFDEFORM_RETURN_IF_ERROR(SolidProblem(stats->solid, "the part", "body"));
  // The body alone: its every wall is the thickness.
  stats->thinnest_wall_mm = request.part.thickness_mm;
  const PartSettings& p = request.part;
  if (p.min_wall_mm > 0 && stats->thinnest_wall_mm < p.min_wall_mm) {
    const std::string thin =
        Format("the wall is %g mm thick, thinner than the printer's minimum of %g mm",
               stats->thinnest_wall_mm, p.min_wall_mm);
    if (p.strict) {
      return Status(ErrorCode::kInvalidArgument, thin + " (strict)", "body.thickness_mm")
          .WithLimit(p.min_wall_mm, stats->thinnest_wall_mm);
    }
    stats->warnings.push_back(thin);
  }
  std::vector<Timing> timings = {{"body", body_ms}, {"check", check_ms}};
  if (report_json) {
    SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, JsonReply(stats->ToJson()));
    reply.timings = std::move(timings);
    return reply;
  }
  proto::OutputOptions output = request.output;
  output.format = format;
  ImportedMesh none;
  EncodeContext encode;
  encode.object_name = "part";
  return MeshReply(part, output, format, none, false, std::move(timings), std::move(stats), encode);
}

}  // namespace surfdeform
