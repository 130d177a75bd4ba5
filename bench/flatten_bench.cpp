// flatten_bench: the paper's Table 1 flatten column and scaling, with the
// default method (stress majorization) side by side with the paper's gradient
// descent and CGAL's ARAP and LSCM parameterizers, in the same run. Prints time
// (surface spec to flat sheet, distances included) and quality together, and
// the ratios; only ratios hold on a shared, noisy machine.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/distance/surface_distance.hpp"
#include "engine/flatten/flatten.hpp"
#include "engine/surface/surface_spec.hpp"
#include "support/surface_file.hpp"
#ifdef SURFDEFORM_HAVE_CGAL
#include "cgal_peer.hpp"
#include "harness.hpp"
#endif

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

struct Measured {
  bool ran = false;
  std::string note;  // "not converged", an error, "skipped"
  double ms = 0.0;   // median
  double stress = 0.0;
  int folded = 0;
  int iterations = 0;
};

using bench::Median;

Measured RunEngine(const Surface& s, int n, FlattenOptions o, int repeat) {
  Measured m;
  std::vector<double> times;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = Clock::now();
    auto r = FlattenSurface(s, {n, n}, o);  // a fresh Flattener: nothing reused
    times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (!r.ok()) {
      m.note = r.status().ToString();
      return m;
    }
    m.stress = r->quality.stress;
    m.folded = r->quality.folded_cells;
    m.iterations = r->quality.iterations;
    if (!r->quality.converged) m.note = "stopped at max_iterations";
  }
  m.ran = true;
  m.ms = Median(times);
  return m;
}

#ifdef SURFDEFORM_HAVE_CGAL
Measured RunCgal(const Surface& s, int n, const std::string& method, int repeat,
                 const SurfaceDistances& dist) {
  Measured m;
  std::vector<double> times;
  bench::PeerResult r;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = Clock::now();
    r = bench::CgalParameterize(s, n, n, method);
    times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (!r.ok) {
      m.note = r.error;
      return m;
    }
  }
  // Quality on the same terms as ours. LSCM's scale is arbitrary (two pinned
  // vertices): give it the uniform scale that minimises its stress.
  std::vector<Vec2> x = r.flat;
  if (method == "lscm") {
    double dl = 0.0, ll = 0.0;
    for (const GridEdge& e : dist.edges) {
      const double l = (x[e.i] - x[e.j]).norm();
      dl += e.d * l;
      ll += l * l;
    }
    for (Vec2& p : x) p *= dl / ll;
  }
  const FlattenQuality q = MeasureLayout(dist, n, n, &x);
  m.ran = true;
  m.ms = Median(times);
  m.stress = q.stress;
  m.folded = q.folded_cells;
  return m;
}
#endif

std::string Cell(const Measured& m, const Measured& ours) {
  char buf[200];
  if (!m.ran) {
    std::snprintf(buf, sizeof buf, "%s", m.note.empty() ? "skipped" : m.note.c_str());
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%.3g ms  stress %.4g  folded %d  (%.1fx)%s%s", m.ms, m.stress,
                m.folded, m.ms / ours.ms, m.note.empty() ? "" : "  ", m.note.c_str());
  return buf;
}

// The periodic flattening of a sphere belt and a torus ring against the
// open flattening of the same surfaces with their seam left cut (a span
// of 360 - 1e-6 degrees: the same samples to 1e-8, not closed).
int RunPeriodic(int repeat) {
  struct Closed {
    const char* name;
    SurfaceSpec closed, cut;
  };
  const Closed cases[] = {
      {"sphere belt (lat +-40)", SphereSpec{1.0, 0.0, 360.0, -40.0, 40.0, {}},
       SphereSpec{1.0, 0.0, 360.0 - 1e-6, -40.0, 40.0, {}}},
      {"torus ring (3, 1; v +-40)", TorusSpec{3.0, 1.0, 0.0, 360.0, -40.0, 40.0, {}},
       TorusSpec{3.0, 1.0, 0.0, 360.0 - 1e-6, -40.0, 40.0, {}}},
      {"torus ring (3, 1; v +-70)", TorusSpec{3.0, 1.0, 0.0, 360.0, -70.0, 70.0, {}},
       TorusSpec{3.0, 1.0, 0.0, 360.0 - 1e-6, -70.0, 70.0, {}}},
  };
  std::printf(
      "flatten r=3, periodic (pairs across the seam, the period solved) vs open (the same "
      "surface cut at its seam); ratio = periodic time / open time\n");
  for (const Closed& c : cases) {
    auto closed = MakeSurface(c.closed);
    auto cut = MakeSurface(c.cut);
    if (!closed.ok() || !cut.ok()) return 1;
    for (int n : {32, 128}) {
      const int reps = n >= 128 ? std::max(1, repeat / 2) : repeat;
      const Measured periodic = RunEngine(**closed, n, {}, reps);
      const Measured open = RunEngine(**cut, n, {}, reps);
      if (!periodic.ran) {
        std::fprintf(stderr, "%s: %s\n", c.name, periodic.note.c_str());
        return 1;
      }
      std::printf("%-26s %3dx%-3d periodic %.3g ms  stress %.4g  it %d | ", c.name, n, n,
                  periodic.ms, periodic.stress, periodic.iterations);
      if (open.ran) {
        std::printf("open %.3g ms  stress %.4g  it %d | %.2fx\n", open.ms, open.stress,
                    open.iterations, periodic.ms / open.ms);
      } else {  // the open strip of a whole ring can fold where it wants to close
        std::printf("open failed: %.60s\n", open.note.c_str());
      }
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace
}  // namespace surfdeform

int main(int argc, char** argv) {
  using namespace surfdeform;
  CLI::App app{
      "Flattening benchmark: majorization (default) vs the paper's gradient descent vs CGAL "
      "ARAP and LSCM, same surfaces, same run."};
  std::vector<int> scaling = {32, 64, 128, 256};
  int repeat = 5;
  int paper_max_iterations = 20000;
  int paper_max_side = 128;
  bool quick = false;
  bool periodic = false;
  app.add_option("--scaling", scaling, "grid sides for the scaling rows (figure 10 surface)")
      ->capture_default_str();
  app.add_option("--repeat", repeat, "runs per method and case (median reported)")
      ->capture_default_str();
  app.add_option("--paper-max-iterations", paper_max_iterations,
                 "cap on the paper method's iterations (a capped run is marked)")
      ->capture_default_str();
  app.add_option("--paper-max-side", paper_max_side, "largest grid side the paper method runs on")
      ->capture_default_str();
  app.add_flag("--quick", quick, "Table 1 rows only, one run each (a smoke test)");
  app.add_flag("--periodic", periodic,
               "surfaces closed in u: the periodic flattening against the open one "
               "of the same surface cut at its seam, at 32^2 and 128^2");
  CLI11_PARSE(app, argc, argv);
  if (periodic) return RunPeriodic(quick ? 1 : repeat);
  if (quick) {
    scaling.clear();
    repeat = 1;
  }

  struct Case {
    std::string file;
    int n;
  };
  std::vector<Case> cases = {{"figure8.json", 10}, {"figure9.json", 10}, {"figure10.json", 16}};
  for (int n : scaling) cases.push_back({"figure10.json", n});

  std::printf(
      "flatten r=3; time = surface spec to flat sheet (distances included); ratios are "
      "peer time / majorization time\n");
  for (const Case& c : cases) {
    auto built = MakeSurface(testing::LoadBezierFile(testing::DataPath(c.file)));
    if (!built.ok()) {
      std::fprintf(stderr, "%s: %s\n", c.file.c_str(), built.status().ToString().c_str());
      return 1;
    }
    const Surface& s = **built;
    const int reps = c.n >= 256 ? 1 : c.n >= 128 ? std::max(1, repeat / 2) : repeat;
    const Measured ours = RunEngine(s, c.n, {}, reps);
    if (!ours.ran) {
      std::fprintf(stderr, "majorization failed: %s\n", ours.note.c_str());
      return 1;
    }
    Measured paper;
    if (c.n <= paper_max_side) {
      FlattenOptions o;
      o.method = FlattenMethod::kPaper;
      o.max_iterations = paper_max_iterations;
      paper = RunEngine(s, c.n, o, c.n >= 64 ? 1 : reps);
    }
    const std::string name = c.file.substr(0, c.file.find('.'));
    std::printf("flatten %-8s %3dx%-3d majorization %.3g ms  stress %.4g  folded %d  it %d\n",
                name.c_str(), c.n, c.n, ours.ms, ours.stress, ours.folded, ours.iterations);
    std::printf("    | paper      %s  it %d\n", Cell(paper, ours).c_str(), paper.iterations);
#ifdef SURFDEFORM_HAVE_CGAL
    DistanceOptions dopt;
    dopt.range = 3;
    auto dist = ComputeSurfaceDistances(s, c.n, c.n, dopt);
    const Measured arap = RunCgal(s, c.n, "arap", reps, *dist);
    const Measured lscm = RunCgal(s, c.n, "lscm", reps, *dist);
    std::printf("    | cgal-arap  %s\n", Cell(arap, ours).c_str());
    std::printf("    | cgal-lscm  %s (stress after best uniform scale)\n",
                Cell(lscm, ours).c_str());
#else
    std::printf("    | cgal       not built (install libcgal-dev)\n");
#endif
    std::fflush(stdout);
  }
  return 0;
}
