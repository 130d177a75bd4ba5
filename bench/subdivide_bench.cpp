// subdivide_bench: vertices added and time of the adaptive subdivision, side
// by side in the same run with `uniform` (every grid point kept, the
// reference): the paper's thin plate on the Figure 8 surface (10x10) and the
// Figure 10 surface at 10x10 and 16x16, and the Stanford bunny on Figure 10
// at 16x16. For each model: uniform's vertices, time and deviation (measured
// at 28 points per output triangle against the exact deformation); adaptive
// asked for that same deviation: vertices, time, deviation and the ratios;
// and adaptive at its default (automatic tolerance).
#include <sys/resource.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

#include "engine/deform/deform.hpp"
#include "harness.hpp"
#include "meshio/mesh_import.hpp"
#include "support/subdivision_check.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"

using namespace surfdeform;
using Clock = std::chrono::steady_clock;

namespace {

struct Run {
  size_t vertices = 0;
  size_t triangles = 0;
  double ms = 0.0;  // median of the whole Deform call
  double subdivide_ms = 0.0;
  double deviation = 0.0;  // dense, against the exact deformation
  double tolerance = 0.0;
};

Run Measure(const testing::Target& t, const Mesh& mesh, const PlacementOptions& o,
            const SubdivisionOptions& s, int repeat) {
  Run run;
  std::vector<double> times, sub_times;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = Clock::now();
    auto r = Deform(SheetMap(*t.surface, t.sheet), Mesh(mesh), {.placement = o, .subdivision = s});
    times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (!r.ok()) {
      std::fprintf(stderr, "deform failed: %s\n", r.status().ToString().c_str());
      std::exit(1);
    }
    sub_times.push_back(r->stats.subdivide_ms);
    run.vertices = r->mesh.positions.size();
    run.triangles = r->mesh.triangles.size();
    run.tolerance = r->stats.subdivision.tolerance;
  }
  std::sort(times.begin(), times.end());
  std::sort(sub_times.begin(), sub_times.end());
  run.ms = times[times.size() / 2];
  run.subdivide_ms = sub_times[sub_times.size() / 2];
  const testing::Refined refined = testing::Refine(t, mesh, o, s);
  run.deviation = testing::DenseDeviation(t, refined, o.outside);
  return run;
}

// This process's CPU time (all threads), ms.
double CpuMs() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-3;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Subdivision benchmark: adaptive vs uniform on the paper's surfaces."};
  int repeat = 9;
  app.add_option("--repeat", repeat, "runs per measurement (median)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  auto bunny = ImportMesh(bench::ReadFile(testing::DataPath("bunny.ply")));
  if (!bunny.ok()) return 1;
  auto figure = [](int n, int grid) {
    return testing::Flattened(
        testing::LoadBezierFile(testing::DataPath("figure" + std::to_string(n) + ".json")), grid);
  };
  struct Case {
    const char* name;
    testing::Target target;
    Mesh mesh;
  };
  Case cases[] = {
      {"thin plate, figure 8 10x10", figure(8, 10), testing::ThinPlate(1, 1, 0.02)},
      {"thin plate, figure 10 10x10", figure(10, 10), testing::ThinPlate(1, 1, 0.02)},
      {"thin plate, figure 10 16x16", figure(10, 16), testing::ThinPlate(1, 1, 0.02)},
      {"thin plate, cylinder 16x16", testing::Flattened(CylinderSpec{1.0, 2.0, 180.0, {}}, 16),
       testing::ThinPlate(1, 1, 0.02)},
      {"bunny, figure 10 16x16", figure(10, 16), bunny->mesh}};
  PlacementOptions o;
  o.fit = true;
  o.fit_margin = 0.05;
  std::printf("subdivision, median of %d runs (time: the whole Deform call | of it subdivision)\n",
              repeat);
  for (const Case& c : cases) {
    SubdivisionOptions uniform;
    uniform.mode = SubdivisionMode::kUniform;
    const Run u = Measure(c.target, c.mesh, o, uniform, repeat);
    SubdivisionOptions same;
    same.tolerance = u.deviation;
    const Run a = Measure(c.target, c.mesh, o, same, repeat);
    const Run d = Measure(c.target, c.mesh, o, SubdivisionOptions{}, repeat);
    const double in_v = static_cast<double>(c.mesh.positions.size());
    std::printf("%s (%zu vertices, %zu triangles in)\n", c.name, c.mesh.positions.size(),
                c.mesh.triangles.size());
    std::printf("  uniform            %8zu v %8zu t  %8.2f | %7.2f ms  deviation %.3g\n",
                u.vertices, u.triangles, u.ms, u.subdivide_ms, u.deviation);
    std::printf(
        "  adaptive, same dev %8zu v %8zu t  %8.2f | %7.2f ms  deviation %.3g  added %.2fx of "
        "uniform's\n",
        a.vertices, a.triangles, a.ms, a.subdivide_ms, a.deviation,
        (static_cast<double>(a.vertices) - in_v) /
            std::max(1.0, static_cast<double>(u.vertices) - in_v));
    std::printf(
        "  adaptive, default  %8zu v %8zu t  %8.2f | %7.2f ms  deviation %.3g (tolerance %.3g)\n",
        d.vertices, d.triangles, d.ms, d.subdivide_ms, d.deviation, d.tolerance);
  }

  // The threads' cost: the whole Deform of the bunny with the default
  // subdivision (placement, the screen, which adds no vertex, and the map) on
  // one thread and on two, wall and process CPU time. On a 2-core machine two
  // threads should halve the wall time at the same CPU.
  const Case& bunny_case = cases[std::size(cases) - 1];
  std::printf("\nbunny's default subdivision by threads (median of %d; wall | CPU ms)\n", repeat);
  for (int threads : {1, 2}) {
    SubdivisionOptions s;
    s.threads = threads;
    PlacementOptions placement = o;
    placement.threads = threads;
    std::vector<double> wall, cpu;
    for (int k = 0; k < repeat; ++k) {
      const double c0 = CpuMs();
      const auto t0 = Clock::now();
      auto r = Deform(SheetMap(*bunny_case.target.surface, bunny_case.target.sheet),
                      Mesh(bunny_case.mesh), {.placement = placement, .subdivision = s});
      wall.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      cpu.push_back(CpuMs() - c0);
      if (!r.ok()) return 1;
    }
    std::sort(wall.begin(), wall.end());
    std::sort(cpu.begin(), cpu.end());
    std::printf("  %d thread%s %8.2f | %7.2f\n", threads, threads > 1 ? "s" : " ",
                wall[wall.size() / 2], cpu[cpu.size() / 2]);
  }
  return 0;
}
