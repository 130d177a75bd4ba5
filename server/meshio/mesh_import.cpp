#include "meshio/mesh_import.hpp"

#include <string>

#include "meshio/importers.hpp"

namespace surfdeform {
namespace meshio {

Status CheckLimit(const char* what, size_t actual, size_t limit) {
  if (actual <= limit) return Status::Ok();
  return Status(ErrorCode::kLimitExceeded,
                std::string("the mesh has ") + std::to_string(actual) + " " + what +
                    "; the limit is " + std::to_string(limit),
                "mesh");
}

void AppendFan(const uint32_t* corners, size_t count, Mesh* mesh) {
  for (size_t k = 1; k + 1 < count; ++k) {
    mesh->triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
}

}  // namespace meshio

Result<ImportedMesh> ImportMesh(std::string_view bytes, const ImportLimits& limits) {
  SURFDEFORM_RETURN_IF_ERROR(meshio::CheckLimit("bytes", bytes.size(), limits.max_bytes));
  ImportedMesh out;
  out.format = DetectMeshFormat(bytes);
  Status status;
  switch (out.format) {
    case MeshFormat::kObj:
      status = meshio::ReadObj(bytes, limits, &out);
      break;
    case MeshFormat::kPly:
      status = meshio::ReadPly(bytes, limits, &out);
      break;
    case MeshFormat::kStl:
      status = meshio::ReadStl(bytes, limits, &out);
      break;
    case MeshFormat::kOff:
      status = meshio::ReadOff(bytes, limits, &out);
      break;
    case MeshFormat::kDraco:
      status = meshio::ReadDraco(bytes, limits, &out);
      break;
    case MeshFormat::kGlb:
    case MeshFormat::kGltf:
      status = meshio::ReadGltf(bytes, out.format == MeshFormat::kGlb, limits, &out);
      break;
    case MeshFormat::kUnknown:
      return Status(ErrorCode::kUnsupportedFormat,
                    "the bytes are in no supported mesh format (glTF/GLB, Draco, OBJ, PLY, STL, "
                    "OFF)",
                    "mesh");
  }
  SURFDEFORM_RETURN_IF_ERROR(status);
  SURFDEFORM_RETURN_IF_ERROR(
      meshio::CheckLimit("vertices", out.mesh.positions.size(), limits.max_vertices));
  SURFDEFORM_RETURN_IF_ERROR(
      meshio::CheckLimit("triangles", out.mesh.triangles.size(), limits.max_triangles));
  if (out.mesh.triangles.empty()) {
    return InvalidArgument("the mesh has no triangles", "mesh");
  }
  if (const std::string problem = CheckMesh(out.mesh); !problem.empty()) {
    return InvalidArgument("malformed mesh: " + problem, "mesh");
  }
  for (size_t k = 0; k < out.mesh.positions.size(); ++k) {
    if (!out.mesh.positions[k].allFinite()) {
      return InvalidArgument("vertex " + std::to_string(k) + " has a non-finite position", "mesh");
    }
  }
  return out;
}

}  // namespace surfdeform
