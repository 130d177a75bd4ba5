// What the server's own readers find in a part's file, for the integration
// tests: kept apart from httplib.h, which must not meet Eigen in one
// translation unit (<resolv.h>'s _res macro).
#pragma once

#include <cstddef>
#include <string>

namespace surfdeform::testing {

struct PrintFile {
  std::string error;   // empty when it was read
  std::string format;  // the importer's name for it ("stl"), or "3mf"
  std::string unit;    // a 3MF's
  size_t objects = 0;  // a 3MF's mesh objects
  size_t build_items = 0;
  size_t vertices = 0;
  size_t triangles = 0;
};

// A 3MF package through lib3mf's reader.
PrintFile Read3mf(const std::string& bytes);
// A mesh file through the server's importer (STL, OBJ, PLY, GLB, Draco).
PrintFile ReadMeshFile(const std::string& bytes);

}  // namespace surfdeform::testing
