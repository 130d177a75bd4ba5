// Writing meshes: Draco .drc, GLB (plain or with KHR_draco_mesh_compression),
// OBJ, PLY, binary STL and 3MF (print_formats.hpp). Output never contains
// NaN or Inf (a non-finite value is an error). OBJ, PLY, plain GLB and Draco with sequential
// encoding keep the vertex order and count (deformed frames can serve as morph targets); Draco's
// edgebreaker (the default) compresses better and reorders.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "meshio/draco_options.hpp"
#include "meshio/mesh_format.hpp"

namespace surfdeform {
namespace meshio {
struct GltfLook;  // gltf_look.hpp
}

// How a GLB carries its vertex data.
enum class GlbEncoding {
  kDraco,      // each primitive with KHR_draco_mesh_compression (the default)
  kPlain,      // float attributes, uncompressed
  kMeshopt,    // quantized (KHR_mesh_quantization), views with EXT_meshopt_compression
  kQuantized,  // kMeshopt's uncompressed twin: the same data, for validators
};

// The order meshoptimizer's codecs compress best (GlbEncoding::kMeshopt and
// kQuantized): each group's triangles ordered for the vertex cache
// (meshopt_optimizeVertexCache) and as the index codec decodes them, and
// the vertices renumbered in the order those triangles first use them
// (meshopt_optimizeVertexFetchRemap), so that neighbours in the buffer are
// neighbours on the mesh; vertices no triangle uses follow, in their order.
// A function of the vertex count, triangles and groups alone: the costly
// part of a meshopt GLB (some 0.5 us per triangle), which a service keeps
// per topology (ExportOptions::meshopt_order).
struct MeshoptOrder {
  std::vector<uint32_t> vertex;                // new index -> the mesh's index
  std::vector<std::vector<uint32_t>> indices;  // per group, in the new numbering
  size_t bytes() const;
};
Result<MeshoptOrder> ComputeMeshoptOrder(const Mesh& mesh);

struct ExportOptions {
  DracoOptions draco;
  GlbEncoding glb = GlbEncoding::kDraco;
  std::vector<std::string> materials;  // names for MeshGroup::material (OBJ usemtl, glTF)
  // GLB: the input's glTF materials, textures and images (ImportedMesh::look),
  // written instead of plain materials named by `materials`.
  std::shared_ptr<const meshio::GltfLook> look;
  int threads = 1;  // for encoders that split their work (GLB pieces, meshopt's buffer views)
  // A Draco GLB of more vertices than this is written in pieces (GlbPieces),
  // encoded in parallel on `threads`; 0: one piece per group.
  size_t split_vertices = 0;
  // The mesh's ComputeMeshoptOrder, when the caller keeps it (null, or one
  // that does not fit the mesh: computed).
  std::shared_ptr<const MeshoptOrder> meshopt_order;
  std::string object_name = "surfdeform";  // a 3MF's one object
};

// A Draco GLB of `vertices` is cut into this many pieces per group: 1 up to
// split_vertices, then the smallest power of two that leaves each piece at
// most split_vertices, up to kMaxGlbPieces. A function of the counts alone,
// so that an answer's bytes do not depend on the threads free to encode it.
inline constexpr int kMaxGlbPieces = 8;
int GlbPieces(size_t vertices, size_t split_vertices);

// Errors: kInvalidArgument for a malformed mesh, non-finite values or bad
// options; kUnsupportedFormat for formats that are read but not written (STL, OFF).
Result<std::string> ExportMesh(const Mesh& mesh, MeshFormat format,
                               const ExportOptions& options = {});

}  // namespace surfdeform
