// Writing meshes: Draco .drc, GLB (plain or with KHR_draco_mesh_compression),
// OBJ and PLY. Output never contains NaN or Inf (a non-finite value is an
// error). OBJ, PLY, plain GLB and Draco with sequential encoding keep the
// vertex order and count (deformed frames can serve as morph targets);
// Draco's edgebreaker (the default) compresses better and reorders.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "base/status.hpp"
#include "engine/mesh.hpp"
#include "meshio/mesh_format.hpp"

namespace surfdeform {
namespace meshio {
struct GltfLook;  // gltf_look.hpp
}

struct DracoOptions {
  // Quantization bits per attribute (Draco's own defaults are 11 / 8 / 10 / 8;
  // these are chosen by measurement: see BENCHMARKS.md).
  int position_bits = 14;
  int normal_bits = 10;
  int uv_bits = 12;
  int color_bits = 8;
  int speed = 5;            // Draco encoder speed 0 (smallest) .. 10 (fastest)
  bool sequential = false;  // keep the vertex order (larger files)
};

struct ExportOptions {
  DracoOptions draco;
  bool glb_draco = true;               // GLB: compress primitives with KHR_draco_mesh_compression
  std::vector<std::string> materials;  // names for MeshGroup::material (OBJ usemtl, glTF)
  // GLB: the input's glTF materials, textures and images (ImportedMesh::look),
  // written instead of plain materials named by `materials`.
  std::shared_ptr<const meshio::GltfLook> look;
};

// Errors: kInvalidArgument for a malformed mesh, non-finite values or bad
// options; kUnsupportedFormat for formats that are read but not written (STL, OFF).
Result<std::string> ExportMesh(const Mesh& mesh, MeshFormat format,
                               const ExportOptions& options = {});

Status ValidateDracoOptions(const DracoOptions& options);

}  // namespace surfdeform
