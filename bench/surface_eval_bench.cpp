// Surface evaluation cost per kind and derivative order (Google Benchmark).
// Deformation evaluates the surface once per vertex, so this bounds its cost.
// Run: ./build/bench/surface_eval_bench
#include <benchmark/benchmark.h>

#include "engine/surface_spec.hpp"
#include "support/surface_file.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

SurfaceSpec SpecOf(int kind) {
  switch (kind) {
    case 0:
      return testing::LoadBezierFile(testing::DataPath("figure10.json"));
    case 1:
      return testing::NurbsCone(1.0, 0.5, 1.0, 240.0);
    case 2:
      return testing::GridCylinder(1.0, 2.0, 180.0, 33, 17);
    case 3:
      return ConeSpec{};
    case 4:
      return TorusSpec{};
    default:
      return WaveSpec{};
  }
}

void BM_Evaluate(benchmark::State& state) {
  auto surface = MakeSurface(SpecOf(static_cast<int>(state.range(0))));
  if (!surface.ok()) {
    state.SkipWithError(surface.status().ToString().c_str());
    return;
  }
  const int order = static_cast<int>(state.range(1));
  state.SetLabel((*surface)->Kind());
  double u = 0.0, v = 0.0;
  for (auto _ : state) {
    // A walk over the patch that does not repeat a point for a long time.
    u += 0.6180339887;
    v += 0.4142135623;
    u -= u >= 1.0 ? 1.0 : 0.0;
    v -= v >= 1.0 ? 1.0 : 0.0;
    benchmark::DoNotOptimize((*surface)->Evaluate(u, v, order));
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_Evaluate)->ArgsProduct({{0, 1, 2, 3, 4, 5}, {0, 1, 2}})->ArgNames({"kind", "order"});

}  // namespace
}  // namespace surfdeform

BENCHMARK_MAIN();
