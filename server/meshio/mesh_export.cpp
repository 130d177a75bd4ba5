#include "meshio/mesh_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "meshio/draco_io.hpp"
#include "meshio/gltf_io.hpp"
#include "meshio/importers.hpp"
#include "meshio/print_formats.hpp"

namespace surfdeform {
namespace {

template <typename V>
bool AllFitFloat(const std::vector<V>& values) {
  return FirstBeyondFloat(values) < 0;
}

void AppendF(std::string* out, const char* format, double a, double b, double c) {
  char buf[96];
  const int n = std::snprintf(buf, sizeof buf, format, a, b, c);
  out->append(buf, static_cast<size_t>(n));
}

std::string WriteObj(const Mesh& m, const ExportOptions& o) {
  std::string s = "# surfdeform\n";
  s.reserve(m.positions.size() * 80 + m.triangles.size() * 40);
  for (size_t k = 0; k < m.positions.size(); ++k) {
    const Vec3& p = m.positions[k];
    if (m.colors.empty()) {
      AppendF(&s, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    } else {
      AppendF(&s, "v %.9g %.9g %.9g", p.x(), p.y(), p.z());
      AppendF(&s, " %.6g %.6g %.6g\n", m.colors[k].x(), m.colors[k].y(), m.colors[k].z());
    }
  }
  for (const Vec2& t : m.uv0) {
    char buf[64];
    const int len = std::snprintf(buf, sizeof buf, "vt %.9g %.9g\n", t.x(), t.y());
    s.append(buf, static_cast<size_t>(len));
  }
  for (const Vec3& n : m.normals) AppendF(&s, "vn %.9g %.9g %.9g\n", n.x(), n.y(), n.z());
  const bool uv = !m.uv0.empty(), nrm = !m.normals.empty();
  auto corner = [&](uint32_t v) {
    const std::string i = std::to_string(v + 1);
    if (uv && nrm) return i + "/" + i + "/" + i;
    if (uv) return i + "/" + i;
    if (nrm) return i + "//" + i;
    return i;
  };
  std::vector<MeshGroup> groups = m.groups;
  if (groups.empty()) groups.push_back({"", -1, 0, static_cast<uint32_t>(m.triangles.size())});
  for (const MeshGroup& g : groups) {
    if (g.material >= 0 && static_cast<size_t>(g.material) < o.materials.size()) {
      s += "usemtl " + o.materials[g.material] + "\n";
    } else if (!g.name.empty()) {
      s += "g " + g.name + "\n";
    }
    for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t) {
      const auto& tri = m.triangles[t];
      s += "f " + corner(tri[0]) + " " + corner(tri[1]) + " " + corner(tri[2]) + "\n";
    }
  }
  return s;
}

template <typename T>
void Put(std::string* out, T value) {
  char buf[sizeof(T)];
  std::memcpy(buf, &value, sizeof(T));  // little-endian hosts only (x86-64, arm64)
  out->append(buf, sizeof(T));
}

std::string WritePly(const Mesh& m) {
  std::string s = "ply\nformat binary_little_endian 1.0\ncomment surfdeform\n";
  s += "element vertex " + std::to_string(m.positions.size()) + "\n";
  s += "property float x\nproperty float y\nproperty float z\n";
  if (!m.normals.empty()) s += "property float nx\nproperty float ny\nproperty float nz\n";
  if (!m.uv0.empty()) s += "property float s\nproperty float t\n";
  if (!m.colors.empty()) {
    s += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
  }
  // s1 - 1 and s2 - 1 (engine/distortion.hpp).
  if (!m.distortion.empty()) s += "property float distortion_max\nproperty float distortion_min\n";
  s += "element face " + std::to_string(m.triangles.size()) + "\n";
  s += "property list uchar int vertex_indices\nend_header\n";
  for (size_t k = 0; k < m.positions.size(); ++k) {
    for (int c = 0; c < 3; ++c) Put(&s, static_cast<float>(m.positions[k][c]));
    if (!m.normals.empty())
      for (int c = 0; c < 3; ++c) Put(&s, static_cast<float>(m.normals[k][c]));
    if (!m.uv0.empty())
      for (int c = 0; c < 2; ++c) Put(&s, static_cast<float>(m.uv0[k][c]));
    if (!m.colors.empty()) {
      for (int c = 0; c < 4; ++c) {
        Put(&s, static_cast<uint8_t>(std::lround(std::clamp(m.colors[k][c], 0.0, 1.0) * 255)));
      }
    }
    if (!m.distortion.empty())
      for (int c = 0; c < 2; ++c) Put(&s, static_cast<float>(m.distortion[k][c]));
  }
  for (const auto& t : m.triangles) {
    Put(&s, static_cast<uint8_t>(3));
    for (uint32_t v : t) Put(&s, static_cast<int32_t>(v));
  }
  return s;
}

}  // namespace

Status ValidateDracoOptions(const DracoOptions& o) {
  auto bits = [](int b, const char* field) {
    if (b < 1 || b > 30) {
      return InvalidArgument("must be from 1 to 30, got " + std::to_string(b), field);
    }
    return Status::Ok();
  };
  SURFDEFORM_RETURN_IF_ERROR(bits(o.position_bits, "output.draco.position_bits"));
  SURFDEFORM_RETURN_IF_ERROR(bits(o.normal_bits, "output.draco.normal_bits"));
  SURFDEFORM_RETURN_IF_ERROR(bits(o.uv_bits, "output.draco.uv_bits"));
  SURFDEFORM_RETURN_IF_ERROR(bits(o.color_bits, "output.draco.color_bits"));
  if (o.speed < 0 || o.speed > 10) {
    return InvalidArgument("must be from 0 to 10, got " + std::to_string(o.speed),
                           "output.draco.speed");
  }
  return Status::Ok();
}

int GlbPieces(size_t vertices, size_t split_vertices) {
  if (split_vertices == 0 || vertices <= split_vertices) return 1;
  int pieces = 2;
  while (pieces < kMaxGlbPieces && vertices > split_vertices * static_cast<size_t>(pieces)) {
    pieces *= 2;
  }
  return pieces;
}

static Result<std::string> ExportClean(const Mesh& mesh, MeshFormat format, const ExportOptions& o);

Result<std::string> ExportMesh(const Mesh& mesh, MeshFormat format, const ExportOptions& o) {
  if (const std::string problem = CheckMesh(mesh); !problem.empty()) {
    return InvalidArgument("malformed mesh: " + problem, "mesh");
  }
  if (!AllFitFloat(mesh.positions) || !AllFitFloat(mesh.normals) || !AllFitFloat(mesh.tangents) ||
      !AllFitFloat(mesh.uv0) || !AllFitFloat(mesh.uv1) || !AllFitFloat(mesh.colors) ||
      !AllFitFloat(mesh.distortion)) {
    return InvalidArgument(
        "the mesh holds a non-finite value, or one beyond the float32 range (1.7e38) that every "
        "output format stores; it is never written",
        "mesh");
  }
  ExportOptions clean = o;
  for (std::string& m : clean.materials) m = meshio::CleanName(m);
  Mesh named;  // names in groups end up in JSON: valid UTF-8 only
  const Mesh* source = &mesh;
  for (const MeshGroup& g : mesh.groups) {
    if (meshio::CleanName(g.name) != g.name) {
      named = mesh;
      for (MeshGroup& ng : named.groups) ng.name = meshio::CleanName(ng.name);
      source = &named;
      break;
    }
  }
  try {
    return ExportClean(*source, format, clean);
  } catch (const std::exception&) {
    return Status(ErrorCode::kInternal, "the mesh could not be written");
  }
}

static Result<std::string> ExportClean(const Mesh& mesh, MeshFormat format,
                                       const ExportOptions& o) {
  switch (format) {
    case MeshFormat::kObj:
      return WriteObj(mesh, o);
    case MeshFormat::kPly:
      return WritePly(mesh);
    case MeshFormat::kDraco:
      return meshio::EncodeDraco(mesh, o.draco);
    case MeshFormat::kGlb:
      return meshio::WriteGlb(mesh, o);
    case MeshFormat::kStl:
      return WriteBinaryStl(mesh);
    case MeshFormat::k3mf:
      return Write3mf(mesh, o.object_name);
    default:
      return Status(ErrorCode::kUnsupportedFormat,
                    std::string("meshes are not written as ") + MeshFormatName(format) +
                        "; choose drc, glb, glb+draco, obj, ply, stl or 3mf",
                    "output.format");
  }
}

}  // namespace surfdeform
