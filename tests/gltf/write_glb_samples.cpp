// Writes the GLB files that the Khronos validator checks (validate.mjs):
// a deformed bunny (also with its distortion map, the custom attribute
// _DISTORTION) and a grid with every attribute and two materials, each plain,
// with KHR_draco_mesh_compression, quantized, and quantized with
// EXT_meshopt_compression. Usage: write_glb_samples DIR
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/deform/deform.hpp"
#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"

using namespace surfdeform;

namespace {

bool Write(const std::string& path, const Mesh& mesh, GlbEncoding encoding,
           const std::vector<std::string>& materials, size_t split_vertices = 0) {
  ExportOptions o;
  o.glb = encoding;
  o.split_vertices = split_vertices;
  o.threads = 2;
  o.materials = materials;
  auto glb = ExportMesh(mesh, MeshFormat::kGlb, o);
  if (!glb.ok()) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), glb.status().ToString().c_str());
    return false;
  }
  std::ofstream(path, std::ios::binary) << *glb;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_glb_samples DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  std::ifstream in(testing::DataPath("bunny.ply"), std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  auto bunny = ImportMesh(bytes.str());
  auto surface = MakeSurface(testing::LoadBezierFile(testing::DataPath("figure10.json")));
  if (!bunny.ok() || !surface.ok()) return 1;
  ComputeVertexNormals(&bunny->mesh);
  auto sheet = FlattenSurface(**surface, {16, 16});
  PlacementOptions placement;
  placement.fit = true;
  auto deformed = Deform(SheetMap(**surface, *sheet), bunny->mesh, {.placement = placement});
  if (!sheet.ok() || !deformed.ok()) return 1;
  auto mapped = Deform(SheetMap(**surface, *sheet), bunny->mesh,
                       {.placement = placement, .distortion = true});
  if (!mapped.ok() || mapped->mesh.distortion.empty()) return 1;
  Mesh grid = testing::FlatGrid(-1, -1, 2, 2, 10, 10, 0.0);
  grid.uv1 = grid.uv0;
  grid.groups = {{"a", 0, 0, 100}, {"b", 1, 100, 100}};
  const std::vector<std::string> materials = {"red", "blue"};
  // Each in every encoding; the validator reads all but meshopt's
  // compressed views (it reports EXT_meshopt_compression as unsupported and
  // checks the rest), so the quantized twin carries the same data uncompressed.
  struct Encoding {
    GlbEncoding glb;
    const char* suffix;
  };
  const Encoding encodings[] = {{GlbEncoding::kPlain, ""},
                                {GlbEncoding::kDraco, "_draco"},
                                {GlbEncoding::kQuantized, "_quantized"},
                                {GlbEncoding::kMeshopt, "_meshopt"}};
  bool ok = true;
  for (const Encoding& e : encodings) {
    ok = ok && Write(dir + "/bunny" + e.suffix + ".glb", deformed->mesh, e.glb, {}) &&
         Write(dir + "/bunny_distortion" + e.suffix + ".glb", mapped->mesh, e.glb, {}) &&
         Write(dir + "/grid" + e.suffix + ".glb", grid, e.glb, materials);
  }
  // A Draco GLB in pieces (four primitives on one quantization grid), which
  // check_glb_pieces.py decodes with draco_decoder.
  Mesh bumpy = testing::FlatGrid(-1, -1, 2, 2, 120, 120, 0.0);
  for (Vec3& p : bumpy.positions) p.z() = 0.2 * std::sin(5.0 * p.x()) * std::cos(4.0 * p.y());
  ok = ok && Write(dir + "/bumpy_pieces.glb", bumpy, GlbEncoding::kDraco, {}, 5000);
  return ok ? 0 : 1;
}
