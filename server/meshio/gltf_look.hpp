// Internal: what a glTF input looks like (its materials, textures, samplers
// and embedded images), carried to GLB output as it came. Images travel as
// their bytes, never decoded: their type is checked by its magic bytes
// (PNG or JPEG, glTF's core image types; others are dropped with a warning)
// and their size counted against the import limits.
#pragma once

#include <tiny_gltf.h>

#include <string>
#include <string_view>
#include <vector>

namespace surfdeform::meshio {

struct GltfLook {
  std::vector<tinygltf::Material> materials;  // MeshGroup::material indexes these
  std::vector<tinygltf::Texture> textures;
  std::vector<tinygltf::Sampler> samplers;
  std::vector<tinygltf::Image> images;   // name and mimeType only; no uri, no bufferView
  std::vector<std::string> image_bytes;  // per image: its file's bytes (empty: dropped)
  std::vector<std::string> extensions;   // KHR_materials_* and KHR_texture_transform used
};

// "image/png" or "image/jpeg" by the bytes' magic numbers, or empty.
std::string_view ImageMediaType(std::string_view bytes);

}  // namespace surfdeform::meshio
