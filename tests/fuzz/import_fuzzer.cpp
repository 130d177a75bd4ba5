// libFuzzer target: ImportMesh on arbitrary bytes, then every writer on what
// it accepted. Build with SURFDEFORM_FUZZ=ON and clang (see tests/fuzz/run.sh).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  surfdeform::ImportLimits limits;
  limits.max_bytes = 1 << 20;
  limits.max_vertices = 100000;
  limits.max_triangles = 200000;
  auto mesh =
      surfdeform::ImportMesh(std::string_view(reinterpret_cast<const char*>(data), size), limits);
  if (!mesh.ok()) return 0;
  for (auto format :
       {surfdeform::MeshFormat::kObj, surfdeform::MeshFormat::kPly, surfdeform::MeshFormat::kGlb}) {
    (void)surfdeform::ExportMesh(mesh->mesh, format);
  }
  return 0;
}
