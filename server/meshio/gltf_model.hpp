// Internal: building a tinygltf::Model for GLB output, shared by the mesh
// writer (gltf_writer.cpp) and the animation writer (animation_glb.cpp).
#pragma once

#include <tiny_gltf.h>

#include <vector>

#include "meshio/gltf_look.hpp"
#include "meshio/mesh_export.hpp"

namespace surfdeform::meshio {

// Appends raw data to buffer 0 as a new buffer view (4-byte aligned); returns
// its index. target: TINYGLTF_TARGET_* or 0. With data null, the view holds
// `bytes` zeros for the caller to fill.
int AddView(tinygltf::Model* m, const void* data, size_t bytes, int target);

// Values as a flat float array of `comps` components each.
template <typename V>
std::vector<float> Floats(const std::vector<V>& values, int comps) {
  std::vector<float> f(values.size() * comps);
  for (size_t k = 0; k < values.size(); ++k)
    for (int c = 0; c < comps; ++c) f[k * comps + c] = static_cast<float>(values[k][c]);
  return f;
}

// A new accessor (view < 0: none, the data are zeros or compressed elsewhere).
int AddAccessor(tinygltf::Model* m, int view, int component, int type, size_t count,
                std::vector<double> min = {}, std::vector<double> max = {});

// The input's look (gltf_look.hpp): its materials, samplers and textures as
// they were, its images' bytes as buffer views (dropped ones removed and the
// textures' sources renumbered), and the material extensions they use.
void AddLook(tinygltf::Model* m, const GltfLook& look);

// The look when there is one, else a plain PBR material per name, in order.
void AddMaterials(tinygltf::Model* m, const ExportOptions& options);

}  // namespace surfdeform::meshio
