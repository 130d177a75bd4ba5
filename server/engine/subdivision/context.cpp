#include "engine/subdivision/context.hpp"

#include <algorithm>
#include <string>

#include "base/format.hpp"
#include "engine/common/elapsed.hpp"
#include "engine/common/parallel.hpp"
#include "engine/subdivision/work_estimate.hpp"

namespace surfdeform::subdivision {

Context::Context(const Mesh& mesh_in, const std::vector<Vec3>& placed_in, const SheetMap& map_in,
                 OutsideMode outside_in, const SubdivisionOptions& o)
    : mesh(mesh_in),
      placed(placed_in),
      map(map_in),
      locator(map_in.locator()),
      options(o),
      grid(locator.nu(), locator.nv()),
      outside(outside_in == OutsideMode::kError ? OutsideMode::kExtrapolate : outside_in),
      refuse_outside(outside_in == OutsideMode::kError),
      threads(mesh_in.triangles.size() >= 2048 ? ResolveThreads(o.threads) : 1),
      uniform(o.mode == SubdivisionMode::kUniform),
      tolerance(o.tolerance),
      refine(false),
      sheet_diagonal(locator.bounds().diagonal().norm()) {
  if (!uniform && tolerance == 0.0 && o.epsilon == 0.0) tolerance = 1e-3 * sheet_diagonal;
  refine = !uniform && tolerance > 0.0;
}

Budget::Budget(const SubdivisionOptions& o, size_t input_vertices)
    : budget_ms_(o.time_budget_ms),
      max_vertices_(o.max_vertices),
      max_crossings_(o.max_crossings),
      input_(input_vertices) {
  deadline_ = DeadlineAfter(start_, o.time_budget_ms, o.cancel);
}

Status Budget::TimeUp() const {
  const double spent = MsSince(start_);
  return Status::DeadlineExceeded(
      "the subdivision did not finish within its time budget of " +
          std::to_string(static_cast<long long>(budget_ms_)) +
          " ms; raise subdivision.tolerance or epsilon, use mode \"off\", or a coarser grid",
      "subdivision", budget_ms_, spent);
}

Status Budget::OverLimitError(const char* what, size_t limit, size_t actual) {
  return Status::LimitExceeded(
      "the subdivision would produce more than " + std::to_string(limit) + " " + what +
          " (the server's limit) at this tolerance; raise subdivision.tolerance or epsilon, or "
          "use a coarser grid",
      "subdivision.tolerance", static_cast<double>(limit), static_cast<double>(actual));
}

Status Budget::TooManyCrossingsError() const {
  return Status::LimitExceeded(
      Format("the model's edges cross the sheet's grid lines (or the surface mesh's edges) more "
             "than %zu times (the server's limit), each a point to measure and maybe keep; "
             "sample the surface more coarsely, lay the model on less of the sheet "
             "(placement.scale), split its long thin triangles, or use subdivision mode "
             "\"off\"",
             max_crossings_),
      "subdivision", static_cast<double>(max_crossings_), static_cast<double>(crossings()));
}

Status Budget::OverLimitError(size_t limit, size_t input, const WorkEstimate& least) {
  const double actual = std::min(static_cast<double>(input) + least.total(), 1e300);
  if (!(least.grid_points <= least.tolerance_points)) {  // the footprint's size (or not finite)
    return Status::LimitExceeded(
        Format("the model's footprint on the sheet (placed, before clamping) spans about %.3g "
               "cells of the sheet's grid: refining it would take the model past %zu vertices "
               "(the server's limit); lay it on less of the sheet (placement.scale or \"fit\", "
               "placement.center) or use subdivision mode \"off\"",
               std::min(least.grid_points, 1e300), limit),
        "placement", static_cast<double>(limit), actual);
  }
  return Status::LimitExceeded(
      Format("meeting subdivision.tolerance %g on this surface's curvature would add at least "
             "%.3g vertices to the model's %zu (estimated before the work), more than the "
             "server's limit of %zu; raise the tolerance or use subdivision mode \"off\"",
             least.tolerance, least.tolerance_points, input, limit),
      "subdivision.tolerance", static_cast<double>(limit), actual);
}

}  // namespace surfdeform::subdivision
