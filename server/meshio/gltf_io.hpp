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
// sharing the vertex accessors (plain) or each compressed with
// KHR_draco_mesh_compression (options.glb_draco).
Result<std::string> WriteGlb(const Mesh& mesh, const ExportOptions& options);

}  // namespace surfdeform::meshio
