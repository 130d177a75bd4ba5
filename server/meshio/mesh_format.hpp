// Mesh file formats and their detection from content.
#pragma once

#include <optional>
#include <string_view>

namespace surfdeform {

// k3mf is written (parts), never read.
enum class MeshFormat { kUnknown, kGlb, kGltf, kDraco, kObj, kPly, kStl, kOff, k3mf };

// "glb", "gltf", "drc", "obj", "ply", "stl", "off", "3mf" ("unknown").
const char* MeshFormatName(MeshFormat format);

// The format named by an extension or a name as above (case-insensitive,
// with or without the dot).
std::optional<MeshFormat> MeshFormatFromName(std::string_view name);

// The format of `bytes` judged from their content alone (magic numbers,
// structure), never from a file name. kUnknown when nothing matches.
MeshFormat DetectMeshFormat(std::string_view bytes);

}  // namespace surfdeform
