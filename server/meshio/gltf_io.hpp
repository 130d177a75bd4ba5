// Internal: glTF 2.0 / GLB reading and GLB writing through tinygltf, with the
// gaps of tinygltf 2.7.0 closed: no file system access (every callback
// refuses), no image decoding (a loader that keeps nothing), a JSON depth
// limit checked before tinygltf parses, and every accessor, buffer view and
// index bounds-checked here before use.
#pragma once

#include <string>
#include <string_view>

#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"

namespace surfdeform::meshio {

// GLB with one node, one mesh and one primitive per MeshGroup, the primitives
// sharing the vertex accessors (plain, quantized, meshopt) or each
// compressed with KHR_draco_mesh_compression, as options.glb says.
Result<std::string> WriteGlb(const Mesh& mesh, const ExportOptions& options);

// GlbEncoding::kMeshopt (compress) and kQuantized: the layout of one frame
// of an animation (animation_glb.hpp), without morph targets:
//  - POSITION as 16-bit normalized integers over the bounding box (error at
//    most 1 / 131068 of its largest side), the node's translation and
//    uniform scale undoing it;
//  - NORMAL and TANGENT as 8-bit normalized integers (as gltfpack's
//    default); TEXCOORD_n as 16-bit normalized integers when they lie in
//    [0, 1], else floats; COLOR_0 as 8-bit; _DISTORTION as floats;
//  - triangles as 32-bit indices in the order meshoptimizer's codec decodes.
Result<std::string> WriteQuantizedGlb(const Mesh& mesh, const ExportOptions& options,
                                      bool compress);

}  // namespace surfdeform::meshio
