#include "print_files.hpp"

#include "meshio/mesh_import.hpp"
#include "meshio/print_formats.hpp"

namespace surfdeform::testing {

PrintFile Read3mf(const std::string& bytes) {
  PrintFile f;
  auto c = Read3mfContents(bytes);
  if (!c.ok()) {
    f.error = c.status().ToString();
    return f;
  }
  f.format = "3mf";
  f.unit = c->unit;
  f.objects = c->objects;
  f.build_items = c->build_items;
  f.vertices = c->vertices;
  f.triangles = c->triangles;
  return f;
}

PrintFile ReadMeshFile(const std::string& bytes) {
  PrintFile f;
  auto read = ImportMesh(bytes);
  if (!read.ok()) {
    f.error = read.status().ToString();
    return f;
  }
  f.format = MeshFormatName(read->format);
  f.vertices = read->mesh.positions.size();
  f.triangles = read->mesh.triangles.size();
  return f;
}

}  // namespace surfdeform::testing
