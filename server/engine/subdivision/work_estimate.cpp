#include "engine/subdivision/work_estimate.hpp"

#include <algorithm>
#include <cmath>

namespace surfdeform::subdivision {

WorkEstimate EstimateWork(const Context& ctx, const LocatedVertices& located,
                          const CellEstimates& estimates) {
  WorkEstimate w;
  w.tolerance = ctx.tolerance;
  const Vec2 extent = ctx.locator.bounds().sizes();
  const double cell_area = extent.x() * extent.y() / std::max(1, ctx.grid.cell_count());
  // The curvature of the cell vertex v lies in (0 off the sheet).
  auto curvature = [&](uint32_t v) {
    const int c = located.cell[VertexId(static_cast<int>(v))];
    return c < 0 ? 0.0 : std::max(0.0, estimates.cell(c).curvature);
  };
  for (const auto& t : ctx.mesh.triangles) {
    const Vec3& p0 = ctx.placed[t[0]];
    const Vec3 e1 = ctx.placed[t[1]] - p0, e2 = ctx.placed[t[2]] - p0;
    const double area = 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
    if (!(area <= 1e300)) {  // not finite, or past any budget
      w.grid_points = HUGE_VAL;
      break;
    }
    if (area > cell_area && cell_area > 0.0) w.grid_points += area / cell_area;
    if (ctx.refine) {
      const double k = std::min({curvature(t[0]), curvature(t[1]), curvature(t[2])});
      w.tolerance_points += area * k / (8.0 * ctx.tolerance);
    }
  }
  return w;
}

}  // namespace surfdeform::subdivision
