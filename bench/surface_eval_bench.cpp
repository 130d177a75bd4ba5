// Surface evaluation cost per kind and derivative order (Google Benchmark).
// Deformation evaluates the surface once per vertex, so this bounds its cost.
// Run: ./build/bench/surface_eval_bench
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "engine/surface/surface_spec.hpp"
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

// A walk over the patch that does not repeat a point for a long time.
struct Walk {
  double u = 0.0, v = 0.0;
  Vec2 Next() {
    u += 0.6180339887;
    v += 0.4142135623;
    u -= u >= 1.0 ? 1.0 : 0.0;
    v -= v >= 1.0 ? 1.0 : 0.0;
    return Vec2(u, v);
  }
};

// The surface of the benchmark's first argument (null, with the error set,
// when it cannot be made); its label names the kind.
std::unique_ptr<Surface> SurfaceOf(benchmark::State& state) {
  auto surface = MakeSurface(SpecOf(static_cast<int>(state.range(0))));
  if (!surface.ok()) {
    state.SkipWithError(surface.status().ToString().c_str());
    return nullptr;
  }
  state.SetLabel((*surface)->Kind());
  return std::move(*surface);
}

void BM_Evaluate(benchmark::State& state) {
  const std::unique_ptr<Surface> surface = SurfaceOf(state);
  if (surface == nullptr) return;
  const int order = static_cast<int>(state.range(1));
  Walk walk;
  for (auto _ : state) {
    const Vec2 p = walk.Next();
    benchmark::DoNotOptimize(surface->Evaluate(p.x(), p.y(), order));
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_Evaluate)->ArgsProduct({{0, 1, 2, 3, 4, 5}, {0, 1, 2}})->ArgNames({"kind", "order"});

// The same walk, 256 points to a call: what the per-vertex map pays per point.
void BM_EvaluateMany(benchmark::State& state) {
  const std::unique_ptr<Surface> surface = SurfaceOf(state);
  if (surface == nullptr) return;
  const int order = static_cast<int>(state.range(1));
  std::vector<Vec2> uv(256);
  Walk walk;
  for (Vec2& p : uv) p = walk.Next();
  std::vector<SurfacePoint> out(uv.size());
  for (auto _ : state) {
    surface->EvaluateMany(uv, order, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(uv.size()));
}

BENCHMARK(BM_EvaluateMany)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {0, 1, 2}})
    ->ArgNames({"kind", "order"});

}  // namespace
}  // namespace surfdeform

BENCHMARK_MAIN();
