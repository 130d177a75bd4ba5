// part_bench: a printable part's server-side work, step by step, beside
// writing its file alone (the least any part service does with the same
// triangles): the body grown from the surface (part/part_body), the checks
// without and with the self-intersection test (part/solid_report, CGAL's
// exact predicates), and binary STL and 3MF (lib3mf) of the same mesh. For
// the ring of 18 mm (the grid its bending asks for) and a whole torus's
// shell at 256^2 and 512^2 samples (262k and 1.05M triangles).
//   build/bench/part_bench [--repeat N]
#include <CLI/CLI.hpp>
#include <cstdio>

#include "engine/surface/surface_spec.hpp"
#include "harness.hpp"
#include "meshio/print_formats.hpp"
#include "part/part_body.hpp"
#include "part/solid_report.hpp"

using namespace surfdeform;
using bench::MedianMs;

namespace {

struct Case {
  const char* name;
  SurfaceSpec spec;
  BodyOptions body;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"part_bench: a part's steps beside writing its file alone"};
  int repeat = 5;
  app.add_option("--repeat", repeat, "Runs per step (the median is kept)");
  CLI11_PARSE(app, argc, argv);

  const TorusSpec torus{10.0, 2.0, 0.0, 360.0, -180.0, 180.0, {}};
  std::vector<Case> cases;
  {
    Case ring{"ring 18 mm, 1.8 mm thick", CylinderSpec{9.0, 6.0, 360.0, {}}, {}};
    ring.body.thickness = 1.8;
    cases.push_back(ring);
    for (int n : {256, 512}) {
      Case t{n == 256 ? "torus shell 256^2" : "torus shell 512^2", torus, {}};
      t.body.thickness = 0.8;
      t.body.side = BodySide::kBoth;
      t.body.nu = t.body.nv = n;
      cases.push_back(t);
    }
  }
  std::printf("%-26s %9s | %8s %8s %9s | %8s %8s | %9s %s\n", "part", "triangles", "body ms",
              "check ms", "+self ms", "stl ms", "3mf ms", "all ms", "all / 3MF alone");
  for (Case& c : cases) {
    auto surface = MakeSurface(c.spec);
    if (!surface.ok()) return 1;
    if (c.body.nu == 64) {  // the default: as the surface bends
      const auto [nu, nv] = BodySamples(**surface);
      c.body.nu = nu;
      c.body.nv = nv;
    }
    Mesh mesh;
    const double body = MedianMs(repeat, [&] { mesh = *ThickenSurface(**surface, c.body); });
    SolidReport report;
    const double check = MedianMs(repeat, [&] { report = CheckSolid(mesh, false); });
    const double full = MedianMs(repeat, [&] { report = CheckSolid(mesh, true); });
    if (!report.sound()) {
      std::fprintf(stderr, "%s: not sound\n", c.name);
      return 1;
    }
    std::string bytes;
    const double stl = MedianMs(repeat, [&] { bytes = WriteBinaryStl(mesh); });
    const double three_mf = MedianMs(repeat, [&] { bytes = *Write3mf(mesh, "part"); });
    const double all = body + full + three_mf;
    std::printf("%-26s %9zu | %8.2f %8.2f %9.2f | %8.2f %8.2f | %9.2f %.2fx\n", c.name,
                mesh.triangles.size(), body, check, full - check, stl, three_mf, all,
                all / three_mf);
  }
  return 0;
}
