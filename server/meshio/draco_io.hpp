// Internal: Draco encoding and decoding of engine meshes, shared by the .drc
// format and glTF's KHR_draco_mesh_compression.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"

namespace surfdeform::meshio {

// The glTF attributes of a Draco-compressed primitive, in the order of
// EncodeDraco's ids.
inline constexpr int kGltfDracoAttributes = 7;
inline constexpr const char* kGltfDracoNames[kGltfDracoAttributes] = {
    "POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0", "TANGENT", "_DISTORTION"};

// One quantization grid for every piece of a mesh encoded in pieces: the
// origin and range Draco would choose for the whole mesh (per attribute type:
// the minimum of each component, the largest extent of any), so that a vertex
// on the border of two pieces decodes to the same bits in both. Normals need
// none (Draco's octahedral coding is a function of the normal alone).
struct DracoGrid {
  std::array<float, 3> position_origin{};
  float position_range = 1.0f;
  std::array<float, 2> uv_origin{};  // both texture coordinate sets
  float uv_range = 1.0f;
  std::array<float, 4> color_origin{};
  float color_range = 1.0f;
};
DracoGrid DracoGridOf(const Mesh& mesh);

// Encodes positions, normals, uv0/uv1, colours and tangents (as a generic
// 4-component attribute). `attribute_ids`, when given (glTF), receives the
// Draco unique ids of kGltfDracoNames (-1 where absent), as glTF's extension
// needs them; only then is Mesh::distortion encoded too (a generic
// 2-component attribute, which only glTF's names tell apart).
// With `grid`, positions, texture coordinates and colours are quantized on
// it instead of on the mesh's own box.
Result<std::string> EncodeDraco(const Mesh& mesh, const DracoOptions& options,
                                int attribute_ids[kGltfDracoAttributes] = nullptr,
                                const DracoGrid* grid = nullptr);

// Decodes a Draco mesh after checking the counts its header claims against the
// limits. With `gltf_ids` (POSITION, NORMAL, TEXCOORD_0, TEXCOORD_1, COLOR_0,
// TANGENT unique ids, -1 if absent) attributes are taken by id, else by type.
Status DecodeDraco(std::string_view bytes, const ImportLimits& limits, Mesh* mesh,
                   const int gltf_ids[6] = nullptr);

}  // namespace surfdeform::meshio
