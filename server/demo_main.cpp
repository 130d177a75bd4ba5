// surfdeform-demo: flattens a built-in surface and prints the flat sheet's
// quality: the engine alone, without the server (see docs/algorithm.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "engine/flatten/flatten.hpp"
#include "engine/surface/surface_spec.hpp"

namespace {

surfdeform::SurfaceSpec Preset(const std::string& name) {
  using namespace surfdeform;
  if (name == "cylinder") return CylinderSpec{1.0, 2.0, 180.0, {}};
  if (name == "cone") return ConeSpec{1.0, 0.5, 1.0, 240.0, {}};
  if (name == "sphere") return SphereSpec{};
  if (name == "torus") return TorusSpec{};
  if (name == "wave") return WaveSpec{};
  // A bumpy bicubic Bezier patch on the unit square.
  BezierSpec b;
  const double h[4][4] = {
      {0, 0.1, 0.1, 0}, {0.1, 0.5, -0.3, 0.1}, {0.1, -0.3, 0.5, 0.1}, {0, 0.1, 0.1, 0}};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) b.control_points.emplace_back(i / 3.0, j / 3.0, h[i][j]);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Flattens a built-in surface and prints the quality of the flat sheet."};
  std::string surface = "bezier";
  int n = 16;
  int range = 3;
  std::string method = "majorization";
  app.add_option("--surface", surface, "bezier, cylinder, cone, sphere, torus or wave")
      ->check(CLI::IsMember({"bezier", "cylinder", "cone", "sphere", "torus", "wave"}))
      ->capture_default_str();
  app.add_option("-n,--samples", n, "samples per side (2..512)")->capture_default_str();
  app.add_option("-r,--range", range, "grid range r of the stress (1..8)")->capture_default_str();
  app.add_option("--method", method, "majorization or paper")
      ->check(CLI::IsMember({"majorization", "paper"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  auto built = surfdeform::MakeSurface(Preset(surface));
  if (!built.ok()) {
    std::fprintf(stderr, "error: %s\n", built.status().ToString().c_str());
    return 2;
  }
  surfdeform::FlattenOptions options;
  options.range = range;
  options.method = method == "paper" ? surfdeform::FlattenMethod::kPaper
                                     : surfdeform::FlattenMethod::kMajorization;
  auto sheet = surfdeform::FlattenSurface(**built, {n, n}, options);
  if (!sheet.ok()) {
    std::fprintf(stderr, "error: %s\n", sheet.status().ToString().c_str());
    return 1;
  }
  const auto& q = sheet->quality;
  std::printf("surface %s  %dx%d  r=%d  method %s\n", surface.c_str(), n, n, range,
              sheet->method.c_str());
  std::printf("  stress          %.3e\n", q.stress);
  std::printf("  max edge error  %.3e\n", q.max_edge_error);
  std::printf("  area ratio      %.4f .. %.4f\n", q.area_ratio_min, q.area_ratio_max);
  std::printf("  folded cells    %d\n", q.folded_cells);
  std::printf("  iterations      %d%s\n", q.iterations, q.converged ? "" : " (not converged)");
  std::printf("  time            %.2f ms (distances %.2f ms, solve %.2f ms)\n", q.total_ms,
              q.distance_ms, q.solve_ms);
  return 0;
}
