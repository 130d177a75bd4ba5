#include "service/engine_options.hpp"

#include "service/limit_checks.hpp"

namespace surfdeform {

FlattenOptions FlattenFor(const FlattenSettings& given, int threads, const RequestClock& clock,
                          double cap_ms) {
  auto f = WithRunDefaults<FlattenOptions>(given);
  f.threads = threads;
  f.time_budget_ms = clock.BudgetFor(cap_ms);
  f.cancel = clock.cancel();
  return f;
}

PlacementOptions PlacementFor(const PlacementSettings& given, const ImportedMesh& m, int threads) {
  auto p = WithRunDefaults<PlacementOptions>(given);
  p.threads = threads;
  p.y_up_input = m.format == MeshFormat::kGlb || m.format == MeshFormat::kGltf;
  p.centre_at_origin = m.centre_at_origin;
  return p;
}

SubdivisionOptions SubdivisionFor(const SubdivisionSettings& given, const ServiceLimits& limits,
                                  const RequestWork& work) {
  auto s = WithRunDefaults<SubdivisionOptions>(given);
  s.threads = work.threads();
  s.max_vertices = MaxOutputVertices(limits);
  s.max_crossings = MaxSubdivisionCrossings(limits);
  s.max_triangles = limits.max_output_triangles;
  s.time_budget_ms = work.clock().BudgetFor(limits.request_time_budget_ms);
  s.cancel = work.clock().cancel();
  return s;
}

}  // namespace surfdeform
