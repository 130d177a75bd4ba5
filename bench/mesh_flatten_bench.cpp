// mesh_flatten_bench: surfaces given as meshes. Irregular
// triangulations (with CGAL: the Delaunay triangulation of random points of
// the parameter square and points evenly along its sides; without: a grid
// with each interior vertex moved at random by up to 0.2 of a cell and each
// cell split along a random diagonal) of half a cylinder and of the paper's
// Figure 10 patch, flattened by FlattenMesh
// and, in the same run, by CGAL's ARAP and LSCM parameterizers. Prints time,
// stress on our terms (pairs within 3 rings), folded triangles, the ratios,
// and for the cylinder each layout's largest distance from the exact
// development after the best rigid motion, against the tessellation's own
// error (the largest chord's shortfall from its arc). With --animate N: an
// animation whose keyframes are meshes (the half cylinder bending), its
// frames flattened warm one after another against each frame alone.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "engine/animation/animation.hpp"
#include "engine/common/disk_mesh.hpp"
#include "engine/flatten/mesh_flatten.hpp"
#include "engine/surface/surface_spec.hpp"
#include "harness.hpp"
#include "support/sheet_compare.hpp"
#include "support/surface_file.hpp"
#ifdef SURFDEFORM_HAVE_CGAL
#include "cgal_peer.hpp"
#endif

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

struct Triangulation {
  std::vector<Vec3> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<Vec2> st;  // each vertex's parameters
};

// About `vertices` vertices over the parameter square, mapped through f.
template <typename F>
Triangulation Irregular(int vertices, unsigned seed, const F& f) {
  Triangulation m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
#ifdef SURFDEFORM_HAVE_CGAL
  const int side = static_cast<int>(std::sqrt(static_cast<double>(vertices)));
  for (int k = 0; k < side; ++k) {  // the sides, evenly
    const double a = static_cast<double>(k) / side;
    m.st.insert(m.st.end(), {Vec2(a, 0), Vec2(1, a), Vec2(1 - a, 1), Vec2(0, 1 - a)});
  }
  while (static_cast<int>(m.st.size()) < vertices) m.st.emplace_back(unit(rng), unit(rng));
  for (const auto& t : bench::DelaunayTriangles(m.st)) {
    m.triangles.push_back(
        {static_cast<uint32_t>(t[0]), static_cast<uint32_t>(t[1]), static_cast<uint32_t>(t[2])});
  }
#else
  const int cells = static_cast<int>(std::sqrt(static_cast<double>(vertices))) - 1;
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  std::bernoulli_distribution flip(0.5);
  const int n = cells + 1;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      double s = static_cast<double>(i) / cells, t = static_cast<double>(j) / cells;
      if (i > 0 && i < cells) s += jitter(rng) / cells;
      if (j > 0 && j < cells) t += jitter(rng) / cells;
      m.st.emplace_back(s, t);
    }
  }
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const uint32_t a = i + n * j, b = a + 1, c = a + 1 + n, d = a + n;
      if (flip(rng)) {
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, d});
      } else {
        m.triangles.push_back({a, b, d});
        m.triangles.push_back({b, c, d});
      }
    }
  }
  (void)unit;
#endif
  for (const Vec2& st : m.st) m.positions.push_back(f(st.x(), st.y()));
  return m;
}

// The largest distance of `flat` from the exact development `exact` after
// the best rigid motion (a layout with clockwise triangles is mirrored
// first: a peer's may be).
double DevelopmentError(std::vector<Vec2> flat, const std::vector<Vec2>& exact,
                        const std::vector<std::array<uint32_t, 3>>& triangles) {
  double area = 0.0;
  for (const auto& t : triangles) area += Cross2(flat[t[1]] - flat[t[0]], flat[t[2]] - flat[t[0]]);
  if (area < 0.0) {
    for (Vec2& p : flat) p.x() = -p.x();
  }
  return testing::RigidError(exact, flat);
}

struct Row {
  std::string method;
  double ms = 0.0;
  FlattenQuality quality;
  double development = -1.0;  // cylinder only
  std::string note;
};

void Print(const Row& r, const Row& ours) {
  std::printf("  %-12s %9.1f ms (%5.2fx ours)  stress %.3e  folded %6d", r.method.c_str(), r.ms,
              r.ms / ours.ms, r.quality.stress, r.quality.folded_cells);
  if (r.development >= 0.0) std::printf("  development error %.3e", r.development);
  std::printf("%s%s\n", r.note.empty() ? "" : "  ", r.note.c_str());
}

// A keyframe of kind "mesh" with its mesh resolved, as the service does.
Keyframe MeshKey(double time, const Triangulation& m) {
  MeshSpec spec;
  spec.model_id = std::to_string(time);
  spec.disk = std::make_shared<const DiskMesh>(*MakeDiskMesh(m.positions, m.triangles));
  return {time, spec};
}

// An animation whose keys are meshes: the half cylinder bending to radius 1.5
// (its arcs as long), `frames` frames, flattened as POST /v1/animate does
// (frame after frame, warm), and each frame's mesh flattened alone (cold,
// as a client deforming along each frame's mesh would) in the same run.
int AnimateMeshes(const std::vector<int>& sizes, int frames) {
  for (int c : sizes) {
    auto bent = [](double radius) {
      return [radius](double s, double t) -> Vec3 {
        const double a = std::numbers::pi * s / radius;
        return Vec3(radius * std::cos(a), radius * std::sin(a), 2.0 * t);
      };
    };
    const Triangulation first = Irregular(c, 1, bent(1.0)), last = Irregular(c, 1, bent(1.5));
    AnimationSpec spec;
    spec.keyframes = {MeshKey(0, first), MeshKey(1, last)};
    spec.interpolation = Interpolation::kLinear;
    spec.frames = frames;
    const auto t0 = Clock::now();
    auto sheets = FlattenAnimation(spec, {32, 32}, FlattenOptions{});
    const double all_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (!sheets.ok()) {
      std::printf("animation: %s\n", sheets.status().ToString().c_str());
      return 1;
    }
    std::vector<double> warm_ms, cold_ms;
    double warm_iterations = 0, cold_iterations = 0, worst = 0.0;
    for (int k = 1; k < frames; ++k) {
      const FlatMesh& warm = *sheets->surfaces[k]->flat_mesh();
      warm_ms.push_back(sheets->frames[k].quality.total_ms);
      warm_iterations += sheets->frames[k].quality.iterations;
      const auto tc = Clock::now();
      auto cold = FlattenMesh(warm.mesh, FlattenOptions{});
      cold_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - tc).count());
      if (!cold.ok()) return 1;
      cold_iterations += cold->quality.iterations;
      worst = std::max(worst,
                       std::abs(warm.quality.stress - cold->quality.stress) / cold->quality.stress);
    }
    const double warm = bench::Median(warm_ms), cold = bench::Median(cold_ms);
    std::printf(
        "mesh animation, %zu vertices, %d frames: %.0f ms in all (%.1f ms a frame with its "
        "sheet); a frame's flattening warm %.1f ms (%.1f iterations), alone %.1f ms (%.1f "
        "iterations): %.2fx; stress within %.1e (relative) of each frame's alone\n",
        first.positions.size(), frames, all_ms, all_ms / frames, warm,
        warm_iterations / (frames - 1), cold, cold_iterations / (frames - 1), cold / warm, worst);
  }
  return 0;
}

int Run(int argc, char** argv) {
  CLI::App app("Surfaces given as meshes: FlattenMesh against CGAL's ARAP and LSCM");
  std::vector<int> sizes = {5000, 50000};
  int repeat = 1;
  int sources = 20;
  int animate = 0;
  app.add_option("--vertices", sizes, "vertices of each triangulation");
  app.add_option("--repeat", repeat, "runs per method (the median is printed)");
  app.add_option("--geodesic-sources", sources,
                 "sources whose pair distances are checked against exact geodesics (meshes of "
                 "at most 10k vertices; 0: none)");
  app.add_option("--animate", animate,
                 "instead: an animation of this many frames whose keyframes are meshes (the "
                 "half cylinder bending), warm frame after frame against each frame alone");
  CLI11_PARSE(app, argc, argv);
  if (animate > 1) return AnimateMeshes(sizes, animate);

  auto figure10 = MakeSurface(testing::LoadBezierFile(testing::DataPath("figure10.json")));
  if (!figure10.ok()) return 1;
  constexpr double kAngle = std::numbers::pi;
  for (int c : sizes) {
    for (int kind = 0; kind < 2; ++kind) {
      const Triangulation m =
          kind == 0 ? Irregular(c, 1,
                                [](double s, double t) -> Vec3 {
                                  return Vec3(std::cos(kAngle * s), std::sin(kAngle * s), 2.0 * t);
                                })
                    : Irregular(c, 2, [&](double s, double t) -> Vec3 {
                        return (*figure10)->Position(s, t);
                      });
      std::vector<Vec2> exact;
      for (const Vec2& st : m.st) exact.emplace_back(kAngle * st.x(), 2.0 * st.y());
      std::printf("%s, %zu vertices, %zu triangles\n",
                  kind == 0 ? "half cylinder (r 1, h 2)" : "figure 10 patch", m.positions.size(),
                  m.triangles.size());
      if (kind == 0) {
        // The chord spanning the most angle: its shortfall from its arc.
        double widest = 0.0;
        for (const auto& t : m.triangles) {
          for (int k = 0; k < 3; ++k) {
            widest = std::max(widest, std::abs(m.st[t[k]].x() - m.st[t[(k + 1) % 3]].x()));
          }
        }
        const double a = kAngle * widest;
        std::printf("  tessellation error: widest edge %.3g rad, chord short of its arc by %.3e\n",
                    a, a - 2 * std::sin(a / 2));
      }
      std::vector<double> times;
      Result<FlatMesh> flat = Status(ErrorCode::kInternal, "not run");
      for (int r = 0; r < repeat; ++r) {
        const auto t0 = Clock::now();
        auto disk = MakeDiskMesh(m.positions, m.triangles);
        if (!disk.ok()) return 1;
        flat = FlattenMesh(std::move(*disk), FlattenOptions{});
        times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        if (!flat.ok()) {
          std::printf("  ours: %s\n", flat.status().ToString().c_str());
          break;
        }
      }
      if (!flat.ok()) continue;
      Row ours{"ours", bench::Median(times), flat->quality, -1.0, ""};
      ours.note = std::to_string(flat->quality.iterations) + " iterations, distances " +
                  std::to_string(static_cast<int>(flat->quality.distance_ms)) + " ms, solve " +
                  std::to_string(static_cast<int>(flat->quality.solve_ms)) + " ms";
      if (kind == 0) ours.development = DevelopmentError(flat->flat, exact, m.triangles);
      Print(ours, ours);
#ifdef SURFDEFORM_HAVE_CGAL
      std::vector<std::array<int, 3>> tris;
      for (const auto& t : m.triangles) {
        tris.push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
      }
      if (sources > 0 && static_cast<int>(m.positions.size()) <= 10000) {
        // Our pair distances against exact geodesics (CGAL's shortest paths)
        // from a few sources, and the straight chord's for scale.
        const std::vector<GridEdge> pairs = MeshPairDistances(*flat, 3);
        double worst = 0.0, sum = 0.0, chord_worst = 0.0;
        size_t count = 0;
        double exact_ms = 0.0;
        const int n = static_cast<int>(m.positions.size());
        for (int k = 0; k < sources; ++k) {
          const int source = static_cast<int>((static_cast<long long>(k) * 7919 + 13) % n);
          const auto t0 = Clock::now();
          const std::vector<double> geodesic = bench::ExactGeodesics(m.positions, tris, source);
          exact_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
          for (const GridEdge& e : pairs) {
            if (e.i != source && e.j != source) continue;
            const int other = e.i == source ? e.j : e.i;
            const double g = geodesic[other];
            const double err = std::abs(e.d - g) / g;
            worst = std::max(worst, err);
            sum += err;
            chord_worst =
                std::max(chord_worst, (g - (m.positions[source] - m.positions[other]).norm()) / g);
            ++count;
          }
        }
        std::printf(
            "  distances: %zu pairs within 3 rings of %d sources against exact geodesics (CGAL "
            "shortest paths, %.0f ms a source): ours off by %.2e at most, %.2e on average; the "
            "straight chord is short by up to %.2e\n",
            count, sources, exact_ms / sources, worst,
            sum / static_cast<double>(std::max<size_t>(count, 1)), chord_worst);
      }
      for (const char* method : {"arap", "lscm"}) {
        std::vector<double> peer_times;
        bench::PeerResult p;
        for (int r = 0; r < repeat; ++r) {
          const auto t0 = Clock::now();
          p = bench::CgalParameterizeMesh(m.positions, tris, method);
          peer_times.push_back(
              std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        }
        Row row{std::string("cgal-") + method, bench::Median(peer_times), {}, -1.0, ""};
        if (!p.ok) {
          row.note = p.error;
          Print(row, ours);
          continue;
        }
        std::vector<Vec2> x = p.flat;
        if (std::string(method) == "lscm") {
          // LSCM's scale is arbitrary: the uniform scale that best fits the edges.
          double dl = 0.0, ll = 0.0;
          for (const auto& t : m.triangles) {
            for (int k = 0; k < 3; ++k) {
              const int a = static_cast<int>(t[k]), b = static_cast<int>(t[(k + 1) % 3]);
              const double l = (x[a] - x[b]).norm();
              dl += (m.positions[a] - m.positions[b]).norm() * l;
              ll += l * l;
            }
          }
          for (Vec2& q : x) q *= dl / ll;
          row.note = "after the best uniform scale";
        }
        row.quality = MeasureMeshLayout(*flat, x);
        if (kind == 0) row.development = DevelopmentError(x, exact, m.triangles);
        Print(row, ours);
      }
#endif
    }
  }
  return 0;
}

}  // namespace
}  // namespace surfdeform

int main(int argc, char** argv) { return surfdeform::Run(argc, argv); }
