#include "engine/surface/sample_grid.hpp"

#include <algorithm>
#include <string>

namespace surfdeform {

Status ValidateSampling(const SamplingOptions& o) {
  for (auto [n, name] : {std::pair{o.nu, "nu"}, std::pair{o.nv, "nv"}}) {
    if (n < kMinGridSide || n > kMaxGridSide) {
      return InvalidArgument("must be from " + std::to_string(kMinGridSide) + " to " +
                                 std::to_string(kMaxGridSide) + ", got " + std::to_string(n),
                             name);
    }
  }
  return Status::Ok();
}

Result<SampledGrid> SampleSurface(const Surface& surface, const SamplingOptions& o) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateSampling(o));
  SampledGrid g;
  g.nu = o.nu;
  g.nv = o.nv;
  const size_t n = static_cast<size_t>(o.nu) * o.nv;
  g.points.resize(n);
  g.normals.resize(n);
  std::vector<Vec3> crosses(n);
  double largest = 0.0;  // the surface's own scale for |Su x Sv|
  for (int j = 0; j < o.nv; ++j) {
    for (int i = 0; i < o.nu; ++i) {
      const double u = static_cast<double>(i) / (o.nu - 1);
      const double v = static_cast<double>(j) / (o.nv - 1);
      const SurfacePoint s = surface.Evaluate(u, v, 1);
      crosses[g.index(i, j)] = s.su.cross(s.sv);
      largest = std::max(largest, crosses[g.index(i, j)].norm());
      g.points[g.index(i, j)] = s.p;
      if (!s.p.allFinite() || !s.su.allFinite() || !s.sv.allFinite()) {
        return Degenerate("the surface is not finite at sample (" + std::to_string(i) + ", " +
                              std::to_string(j) + ")",
                          "surface");
      }
    }
  }
  for (int j = 0; j < o.nv; ++j) {
    for (int i = 0; i < o.nu; ++i) {
      const double u = static_cast<double>(i) / (o.nu - 1);
      const double v = static_cast<double>(j) / (o.nv - 1);
      const Vec3& cross = crosses[g.index(i, j)];
      auto where = [&] {
        return "sample (" + std::to_string(i) + ", " + std::to_string(j) + ") at (u, v) = (" +
               std::to_string(u) + ", " + std::to_string(v) + ")";
      };
      // |Su x Sv| = |Su| |Sv| sin(angle) vanishes where either derivative does
      // (a pole, an apex) or where they are parallel; "vanishes" is relative to
      // the largest value over the grid.
      if (!(cross.norm() > 1e-9 * largest)) {
        return Degenerate("the surface normal vanishes at " + where() +
                              " (a pole, an apex or collapsed control points)",
                          "surface");
      }
      g.normals[g.index(i, j)] = cross.normalized();
    }
  }
  return g;
}

}  // namespace surfdeform
