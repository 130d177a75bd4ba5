// The subdivision's pipeline: each stage in server/engine/subdivision/.
#include "engine/subdivision/subdivide.hpp"

#include <chrono>
#include <cmath>
#include <optional>

#include "engine/common/elapsed.hpp"
#include "engine/subdivision/assembly.hpp"
#include "engine/subdivision/screen.hpp"
#include "engine/subdivision/target_edges.hpp"
#include "engine/subdivision/work_estimate.hpp"

namespace surfdeform {
namespace {

using namespace subdivision;

// What the caller gets of the input vertices' positions.
void HandOverPositions(InputPositions want, LocatedVertices* located, SubdivisionResult* r) {
  r->on_sheet = std::move(located->on_sheet.raw());
  if (want == InputPositions::kWanted) r->input_positions = std::move(located->deformed.raw());
}

Result<SubdivisionResult> Run(const Context& ctx, InputPositions want) {
  const auto t0 = std::chrono::steady_clock::now();
  Budget budget(ctx.options, ctx.mesh.positions.size());
  SubdivisionStats stats;
  stats.mode = ctx.options.mode;
  stats.vertices_before = ctx.mesh.positions.size();
  stats.triangles_before = ctx.mesh.triangles.size();
  stats.epsilon = ctx.uniform ? 0.0 : ctx.options.epsilon;
  stats.tolerance = ctx.refine ? ctx.tolerance : 0.0;

  SURFDEFORM_ASSIGN_OR_RETURN(LocatedVertices located,
                              LocateVertices(ctx, want == InputPositions::kWanted));
  const CellEstimates estimates(ctx, located.cell);
  if (const ScreenResult screen = Screen(ctx, located, estimates); screen.pass) {
    SubdivisionResult r;
    r.unchanged = true;
    r.stats = stats;
    r.stats.max_estimated_deviation = screen.max_estimate;
    r.stats.max_deviation = screen.max_deviation;
    r.stats.measured_points = screen.measured_points;
    r.stats.vertices_after = r.stats.vertices_before;
    r.stats.triangles_after = r.stats.triangles_before;
    HandOverPositions(want, &located, &r);
    r.stats.time_ms = MsSince(t0);
    return r;
  }
  // Each stage is bounded by the input's size; the refinement, by the output
  // limits and the time budget; and a request whose least work passes the
  // output limit is refused before any of it.
  const size_t input = ctx.mesh.positions.size();
  if (const WorkEstimate least = EstimateWork(ctx, located, estimates);
      !(static_cast<double>(input) + least.total() <=
        static_cast<double>(ctx.options.max_vertices))) {
    return Budget::OverLimitError(ctx.options.max_vertices, input, least);
  }
  if (budget.OutOfTime()) return budget.TimeUp();
  const EdgeGraph graph = BuildEdgeGraph(ctx.mesh);
  if (budget.OutOfTime()) return budget.TimeUp();
  CompleteDeformed(ctx, &located);
  if (budget.OutOfTime()) return budget.TimeUp();
  GridMarking marking = FindGridPoints(ctx, graph, located.cell, estimates, &budget);
  if (budget.TooManyCrossings()) return budget.TooManyCrossingsError();
  if (budget.OutOfTime()) return budget.TimeUp();
  MarkGridPoints(ctx, graph, &marking);
  if (budget.OutOfTime()) return budget.TimeUp();
  const IdVector<EdgeId, RefinedEdge> edges =
      RefineEdges(ctx, graph, marking, located, estimates, &budget);
  if (budget.OverLimit()) {
    return Budget::OverLimitError("vertices", ctx.options.max_vertices, budget.vertices());
  }
  if (budget.OutOfTime()) return budget.TimeUp();
  const FaceStageInputs inputs{ctx, graph, marking, edges, located, estimates};
  const IdVector<FaceId, FaceOutput> faces = RefineFaces(inputs, &budget);
  if (budget.OverLimit()) {
    return Budget::OverLimitError("vertices", ctx.options.max_vertices, budget.vertices());
  }
  if (budget.OutOfTime()) return budget.TimeUp();
  for (const FaceOutput& f : faces) {
    if (f.failed) {
      return Status(ErrorCode::kInternal, "the subdivision could not re-triangulate a face");
    }
  }
  SURFDEFORM_ASSIGN_OR_RETURN(SubdivisionResult r,
                              Assemble(ctx, graph, marking, edges, faces, stats));
  HandOverPositions(want, &located, &r);
  r.stats.time_ms = MsSince(t0);
  return r;
}

}  // namespace

const char* SubdivisionModeName(SubdivisionMode mode) {
  const std::string_view name = NameOf<SubdivisionMode>(kSubdivisionModes, mode);
  return name.empty() ? "off" : name.data();  // the table's literals end in NUL
}

Status ValidateSubdivisionSettings(const SubdivisionSettings& o) {
  if (!(std::isfinite(o.epsilon) && o.epsilon >= 0.0)) {
    return InvalidArgument("must be a finite number >= 0 (1 / surface units; 0 = none)",
                           "subdivision.epsilon");
  }
  if (!(std::isfinite(o.tolerance) && o.tolerance >= 0.0)) {
    return InvalidArgument("must be a finite number >= 0 (surface units; 0 = automatic)",
                           "subdivision.tolerance");
  }
  return Status::Ok();
}

Status ValidateSubdivision(const SubdivisionOptions& o) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateSubdivisionSettings(o));
  if (o.max_vertices == 0 || o.max_triangles == 0 || o.max_crossings == 0) {
    return InvalidArgument("the output size limits must be positive", "subdivision");
  }
  if (o.threads < 0 || o.threads > 256) {
    return InvalidArgument("must be from 0 to 256", "subdivision.threads");
  }
  if (!(std::isfinite(o.time_budget_ms) && o.time_budget_ms >= 0.0)) {
    return InvalidArgument("must be a finite number >= 0 (milliseconds; 0 = none)",
                           "subdivision.time_budget_ms");
  }
  return Status::Ok();
}

Result<SubdivisionResult> Subdivide(const Mesh& mesh, const std::vector<Vec3>& placed,
                                    const SheetMap& map, OutsideMode outside,
                                    const SubdivisionOptions& options, InputPositions want,
                                    std::span<const FaceExtent> extents,
                                    const FootprintUse& footprint) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateSubdivision(options));
  if (placed.size() != mesh.positions.size()) {
    return InvalidArgument("one placed position per vertex is needed", "mesh");
  }
  if (options.mode == SubdivisionMode::kOff) {
    SubdivisionResult r;
    r.unchanged = true;
    r.stats.vertices_before = r.stats.vertices_after = mesh.positions.size();
    r.stats.triangles_before = r.stats.triangles_after = mesh.triangles.size();
    return r;
  }
  Context ctx(mesh, placed, map, outside, options);
  if (extents.size() == mesh.triangles.size()) ctx.extents = extents;
  ctx.footprint = footprint;
  std::optional<TargetEdges> target;
  if (const FlatMesh* flat = map.surface().flat_mesh()) {
    target.emplace(*flat, map.sheet().frame_linear, map.sheet().frame_offset);
    ctx.target = &*target;
  }
  return Run(ctx, want);
}

}  // namespace surfdeform
