// Formats for printing a part: binary STL and 3MF (through lib3mf, the
// 3MF Consortium's library), both in millimetres. One object, positions
// only (triangles are written as they are: a part's outward winding).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "base/status.hpp"
#include "engine/common/mesh.hpp"

namespace surfdeform {

// Binary STL: an 80-byte header, the count, and each triangle's unit normal
// (from its winding) and corners as float32.
std::string WriteBinaryStl(const Mesh& mesh);

// A 3MF package of one mesh object named `name`, unit millimetre, one build item.
Result<std::string> Write3mf(const Mesh& mesh, const std::string& name);

// What lib3mf's reader finds in a 3MF package: for tests and the CLI.
struct ThreeMfContents {
  std::string unit;  // "millimeter", "inch", ...
  size_t objects = 0;
  size_t build_items = 0;
  size_t vertices = 0;  // over its mesh objects
  size_t triangles = 0;
};
Result<ThreeMfContents> Read3mfContents(std::string_view bytes);

}  // namespace surfdeform
