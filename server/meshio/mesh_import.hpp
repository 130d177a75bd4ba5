// Reading meshes from untrusted bytes. The only code that parses mesh files.
//
// Formats: glTF 2.0 (JSON with embedded data: buffers) and GLB, both with
// KHR_draco_mesh_compression and KHR_mesh_quantization; Draco .drc; OBJ; PLY
// (ascii and binary); STL (ascii and binary); OFF. The format is judged from
// the bytes (DetectMeshFormat), never from a name.
//
// Safety: nothing here touches the file system or decodes images; every
// count is checked against the limits and against the number of bytes that
// could hold it before anything is allocated; every index and accessor is
// bounds-checked. Errors say what is wrong and where (line, element,
// accessor) and never contain server paths. Polygons (quads, n-gons, concave
// ones too) are triangulated by ear clipping.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "meshio/mesh_format.hpp"

namespace surfdeform {

struct ImportLimits {
  size_t max_bytes = 256u << 20;    // input size
  size_t max_vertices = 4'000'000;  // after triangulation and welding
  size_t max_triangles = 8'000'000;
  // Groups (runs of triangles of one material, OBJ g/o groups, glTF
  // primitives): each becomes a primitive of a glTF answer.
  size_t max_groups = 4096;
  int max_json_depth = 64;             // glTF JSON nesting
  size_t max_image_bytes = 64u << 20;  // glTF: embedded images, in all (kept, never decoded)
};

namespace meshio {
struct GltfLook;  // gltf_look.hpp
}

struct TextStats;

struct ImportedMesh {
  Mesh mesh;
  MeshFormat format = MeshFormat::kUnknown;
  std::vector<std::string> materials;  // MeshGroup::material indexes this
  std::vector<std::string> warnings;   // what was ignored (points, lines, skins, ...)
  // glTF input: its materials, textures and images, for glTF output; else null.
  std::shared_ptr<const meshio::GltfLook> look;
  // Made from a text (not imported): its origin is the footprint's centre,
  // and its account (glyphs, lines, runs), for the reply's statistics, is
  // the service's (service/text_models.hpp), opaque here.
  bool centre_at_origin = false;
  std::shared_ptr<const TextStats> text_stats;
};

// Errors: kUnsupportedFormat (no format recognised), kLimitExceeded (with the
// limit and the actual value), kInvalidArgument (malformed; field "mesh").
Result<ImportedMesh> ImportMesh(std::string_view bytes, const ImportLimits& limits = {});

}  // namespace surfdeform
