// delivery_bench: what an answer costs to encode and to send, per encoding,
// on the sample models deformed onto Figure 10. For each model
// and each encoding (Draco .drc, GLB with Draco, GLB with meshopt, the
// same with the vertex order a service keeps per model, the quantized GLB
// uncompressed, plain GLB): the encode time (median), the
// bytes raw and after gzip (zlib level 6, what a server's Content-Encoding
// would add; level 1 too), and the ratios to the Draco GLB measured in the
// same run.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "engine/deform/deform.hpp"
#include "engine/flatten/flatten.hpp"
#include "engine/surface/surface.hpp"
#include "harness.hpp"
#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"
#include "service/content_coding.hpp"
#include "service/service_limits.hpp"
#include "support/expect_ok.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"

namespace surfdeform {
namespace {

size_t GzipBytes(const std::string& data, int level) { return Gzip(data, level).size(); }

// A relief like a scan: a grid over the unit square, (side + 1)^2 vertices,
// with bumps, positions and normals only.
Mesh Relief(int side) {
  Mesh m = testing::FlatGrid(0.0, 0.0, 1.0, 1.0, side, side, 0.0);
  m.tangents.clear();
  m.uv0.clear();
  m.colors.clear();
  for (Vec3& p : m.positions) {
    p.z() = 0.02 * std::sin(40.0 * p.x()) * std::cos(30.0 * p.y()) + 0.01 * std::sin(7.0 * p.x());
  }
  m.normals.clear();
  ComputeVertexNormals(&m);
  return m;
}

struct Encoding {
  const char* name;
  MeshFormat format;
  GlbEncoding glb;
  bool order_kept = false;  // meshopt: the vertex order computed before (a model that comes back)
  bool split = false;       // Draco GLB in pieces past --split-vertices, on every core
};

int Run(int repeat, int relief_side, size_t split_vertices) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const BezierSpec fig10 = testing::LoadBezierFile(testing::DataPath("figure10.json"));
  auto surface = MakeSurface(fig10);
  testing::ExpectOk(surface);
  auto sheet = FlattenSurface(**surface, {16, 16});
  testing::ExpectOk(sheet);

  struct Model {
    std::string name;
    Mesh mesh;
  };
  std::vector<Model> models;
  for (const char* file : {"bunny.ply", "word.obj"}) {
    auto imported = ImportMesh(bench::ReadFile(testing::DataPath(file)));
    testing::ExpectOk(imported);
    if (imported->mesh.normals.empty()) ComputeVertexNormals(&imported->mesh);
    models.push_back({file, std::move(imported->mesh)});
  }
  models.push_back({"relief " + std::to_string(relief_side + 1) + "^2", Relief(relief_side)});

  const Encoding encodings[] = {
      {"drc", MeshFormat::kDraco, GlbEncoding::kDraco},
      {"glb draco", MeshFormat::kGlb, GlbEncoding::kDraco},
      {"  in pieces", MeshFormat::kGlb, GlbEncoding::kDraco, false, true},
      {"glb meshopt", MeshFormat::kGlb, GlbEncoding::kMeshopt},
      {"  order kept", MeshFormat::kGlb, GlbEncoding::kMeshopt, true},
      {"glb quantized", MeshFormat::kGlb, GlbEncoding::kQuantized},
      {"glb plain", MeshFormat::kGlb, GlbEncoding::kPlain},
  };
  std::printf(
      "delivery_bench: deformed onto Figure 10 (16x16, fit, subdivision off), %d runs "
      "(medians); gzip = zlib level 6 (level 1 in brackets); \"in pieces\": past %zu "
      "vertices, %d threads\n\n",
      repeat, split_vertices, cores);
  std::printf("%-16s %-14s %9s %8s %11s %11s %13s %9s %9s\n", "model", "encoding", "vertices", "ms",
              "ns/vertex", "bytes", "gzip", "ms/draco", "gz/draco");
  for (const Model& model : models) {
    PlacementOptions placement;
    placement.fit = true;
    SubdivisionOptions off;
    off.mode = SubdivisionMode::kOff;
    auto deformed = Deform(SheetMap(**surface, *sheet), Mesh(model.mesh),
                           {.placement = placement, .subdivision = off});
    testing::ExpectOk(deformed);
    const Mesh& mesh = deformed->mesh;
    const double n = static_cast<double>(mesh.positions.size());
    double draco_ms = 0.0;
    size_t draco_gz = 0;
    for (const Encoding& e : encodings) {
      ExportOptions o;
      o.glb = e.glb;
      if (e.split) {
        o.split_vertices = split_vertices;
        o.threads = cores;
      }
      if (e.order_kept) {
        auto order = ComputeMeshoptOrder(mesh);
        testing::ExpectOk(order);
        o.meshopt_order = std::make_shared<const MeshoptOrder>(std::move(*order));
      }
      std::string bytes;
      const double ms = bench::MedianMs(repeat, [&] {
        auto r = ExportMesh(mesh, e.format, o);
        testing::ExpectOk(r);
        bytes = std::move(*r);
      });
      const size_t gz6 = GzipBytes(bytes, 6), gz1 = GzipBytes(bytes, 1);
      if (std::string(e.name) == "glb draco") {
        draco_ms = ms;
        draco_gz = gz6;
      }
      std::printf("%-16s %-14s %9.0f %8.2f %11.0f %11zu %6zu (%6zu) %9.2f %9.2f\n",
                  model.name.c_str(), e.name, n, ms, 1e6 * ms / n, bytes.size(), gz6, gz1,
                  draco_ms > 0 ? ms / draco_ms : 0.0,
                  draco_gz > 0 ? static_cast<double>(gz6) / static_cast<double>(draco_gz) : 0.0);
    }
    std::printf("\n");
  }
  return 0;
}

}  // namespace
}  // namespace surfdeform

int main(int argc, char** argv) {
  CLI::App app{"Encode time and bytes per answer encoding"};
  int repeat = 5;
  int relief_side = 776;  // 777^2 = 603,729 vertices
  app.add_option("--repeat", repeat, "runs per encoding (the median is printed)");
  app.add_option("--relief-side", relief_side, "quads per side of the relief");
  size_t split_vertices = surfdeform::ServiceLimits{}.glb_split_vertices;
  app.add_option("--split-vertices", split_vertices,
                 "a Draco GLB past this many vertices is written in pieces (the server's default)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  return surfdeform::Run(repeat, relief_side, split_vertices);
}
