// edit_bench: a person editing a surface, as the viewer's live edits do it:
// the paper's Figure 10 sampled 16^2, 32^2 and 64^2, one control point
// raised by 1% of the patch per edit, 30 edits. Each edit flattened cold (a
// fresh flattening, what POST /v1/surfaces does without "warm_start") and
// warm (starting from the previous edit's sheet moved on along the change
// the edit before made to it, with the paths its distances followed and the
// factored Laplacian kept, as the service does), in the same run; per edit, the medians and their
// ratio, the iterations, and the largest relative stress difference.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "engine/flatten/flatten.hpp"
#include "engine/surface/surface_spec.hpp"
#include "harness.hpp"
#include "support/surface_file.hpp"

namespace surfdeform {
namespace {

struct EditRun {
  std::vector<double> cold_ms, warm_ms;
  std::vector<double> cold_distance_ms, warm_distance_ms;  // the distances' part
  int cold_iterations = 0, warm_iterations = 0;            // summed
  double worst_stress = 0.0;                               // relative difference, over the edits
};

EditRun Edits(const BezierSpec& base, int n, int edits, int threads, bool trend) {
  FlattenOptions o;
  o.threads = threads;
  EditRun run;
  BezierSpec spec = base;
  auto first = MakeSurface(SurfaceSpec(spec));
  Flattener warm_flattener(o);  // kept across edits, as a live session keeps its sheet
  // The paths each edit's distances followed, kept beside its sheet for the
  // next, as the service keeps them for surfaces made to be edited.
  DistancePaths paths;
  auto previous = warm_flattener.Flatten(**first, {n, n}, nullptr, nullptr, &paths);
  SheetTrend heading;  // how the previous edit changed the sheet
  for (int e = 0; e < edits; ++e) {
    spec.control_points[5].z() += 0.1;  // 1% of the 10-unit patch
    auto surface = MakeSurface(SurfaceSpec(spec));
    auto t0 = std::chrono::steady_clock::now();
    auto cold = FlattenSurface(**surface, {n, n}, o);
    run.cold_ms.push_back(bench::MsSince(t0));
    t0 = std::chrono::steady_clock::now();
    DistancePaths followed;
    auto warm = warm_flattener.Flatten(**surface, {n, n}, &*previous, &paths, &followed,
                                       trend ? &heading : nullptr);
    paths = std::move(followed);
    if (warm.ok()) heading = TrendBetween(*previous, *warm);
    run.warm_ms.push_back(bench::MsSince(t0));
    if (!cold.ok() || !warm.ok()) {
      std::fprintf(stderr, "edit %d failed: %s\n", e,
                   (cold.ok() ? warm.status() : cold.status()).ToString().c_str());
      std::exit(1);
    }
    run.cold_distance_ms.push_back(cold->quality.distance_ms);
    run.warm_distance_ms.push_back(warm->quality.distance_ms);
    run.cold_iterations += cold->quality.iterations;
    run.warm_iterations += warm->quality.iterations;
    run.worst_stress =
        std::max(run.worst_stress,
                 std::abs(warm->quality.stress - cold->quality.stress) / cold->quality.stress);
    previous = std::move(warm);
  }
  return run;
}

}  // namespace
}  // namespace surfdeform

int main(int argc, char** argv) {
  using namespace surfdeform;
  CLI::App app{"edit_bench: live edits of Figure 10, warm against cold"};
  int edits = 30, threads = 1;
  bool no_trend = false;
  std::vector<int> sides = {16, 32, 64};
  app.add_option("--edits", edits, "edits per grid");
  app.add_option("--sides", sides, "grid sides");
  app.add_option("--threads", threads, "threads per flattening");
  app.add_flag("--no-trend", no_trend, "warm edits start from the previous sheet as it is");
  CLI11_PARSE(app, argc, argv);
  const BezierSpec figure10 = testing::LoadBezierFile(testing::DataPath("figure10.json"));
  std::printf("%-6s %10s %10s %8s %12s %12s %11s %11s %12s\n", "grid", "cold ms", "warm ms",
              "ratio", "cold dist", "warm dist", "cold iters", "warm iters", "stress diff");
  for (int n : sides) {
    const EditRun r = Edits(figure10, n, edits, threads, !no_trend);
    const double cold = bench::Median(r.cold_ms), warm = bench::Median(r.warm_ms);
    std::printf("%3dx%-3d %9.2f %10.2f %8.2f %12.2f %12.2f %11.1f %11.1f %12.1e\n", n, n, cold,
                warm, warm / cold, bench::Median(r.cold_distance_ms),
                bench::Median(r.warm_distance_ms), static_cast<double>(r.cold_iterations) / edits,
                static_cast<double>(r.warm_iterations) / edits, r.worst_stress);
  }
  return 0;
}
