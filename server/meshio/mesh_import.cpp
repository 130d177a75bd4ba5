#include "meshio/mesh_import.hpp"

#include <array>
#include <cmath>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "meshio/importers.hpp"

namespace surfdeform {
namespace meshio {

std::string CleanName(std::string_view text, size_t max_bytes) {
  std::string out;
  for (size_t i = 0; i < text.size() && out.size() < max_bytes;) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    size_t len = c < 0x80           ? 1
                 : (c >> 5) == 0x6  ? 2
                 : (c >> 4) == 0xE  ? 3
                 : (c >> 3) == 0x1E ? 4
                                    : 0;
    bool valid = len > 0 && i + len <= text.size() && !(len == 1 && c < 0x20);
    for (size_t k = 1; valid && k < len; ++k) {
      valid = (static_cast<unsigned char>(text[i + k]) >> 6) == 0x2;
    }
    if (valid && len == 2 && c < 0xC2) valid = false;  // overlong
    if (valid) {
      out.append(text.substr(i, len));
      i += len;
    } else {
      out.push_back('?');
      ++i;
    }
  }
  return out;
}

Status CheckLimit(const char* what, size_t actual, size_t limit) {
  if (actual <= limit) return Status::Ok();
  return Status::LimitExceeded(std::string("the mesh has ") + std::to_string(actual) + " " + what +
                                   "; the limit is " + std::to_string(limit),
                               "mesh", static_cast<double>(limit), static_cast<double>(actual));
}

void AppendPolygon(const uint32_t* corners, const Vec3* positions, size_t count, Mesh* mesh) {
  if (count == 3) {
    mesh->triangles.push_back({corners[0], corners[1], corners[2]});
    return;
  }
  // Newell's normal gives the polygon's plane and orientation.
  Vec3 normal = Vec3::Zero();
  for (size_t k = 0; k < count; ++k) {
    const Vec3& a = positions[k];
    const Vec3& b = positions[(k + 1) % count];
    normal += Vec3((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                   (a.x() - b.x()) * (a.y() + b.y()));
  }
  auto fan = [&] {
    for (size_t k = 1; k + 1 < count; ++k) {
      mesh->triangles.push_back({corners[0], corners[k], corners[k + 1]});
    }
  };
  if (!(normal.norm() > 0.0)) return fan();
  const Vec3 n = normal.normalized();
  const Vec3 e1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  const Vec3 e2 = n.cross(e1);
  std::vector<Vec2> p(count);
  for (size_t k = 0; k < count; ++k) p[k] = Vec2(positions[k].dot(e1), positions[k].dot(e2));
  auto cross = [](const Vec2& a, const Vec2& b, const Vec2& c) {
    return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  };
  std::vector<size_t> ring(count);
  for (size_t k = 0; k < count; ++k) ring[k] = k;
  std::vector<std::array<uint32_t, 3>> out;
  while (ring.size() > 3) {
    bool clipped = false;
    for (size_t k = 0; k < ring.size() && !clipped; ++k) {
      const size_t a = ring[(k + ring.size() - 1) % ring.size()], b = ring[k],
                   c = ring[(k + 1) % ring.size()];
      if (cross(p[a], p[b], p[c]) <= 0.0) continue;  // reflex or flat corner
      bool empty = true;
      for (size_t q : ring) {
        if (q == a || q == b || q == c) continue;
        if (cross(p[a], p[b], p[q]) >= 0 && cross(p[b], p[c], p[q]) >= 0 &&
            cross(p[c], p[a], p[q]) >= 0) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      out.push_back({corners[a], corners[b], corners[c]});
      ring.erase(ring.begin() + static_cast<long>(k));
      clipped = true;
    }
    if (!clipped) return fan();  // no ear: not a simple polygon
  }
  out.push_back({corners[ring[0]], corners[ring[1]], corners[ring[2]]});
  mesh->triangles.insert(mesh->triangles.end(), out.begin(), out.end());
}

}  // namespace meshio

Result<ImportedMesh> ImportMesh(std::string_view bytes, const ImportLimits& limits) {
  SURFDEFORM_RETURN_IF_ERROR(meshio::CheckLimit("bytes", bytes.size(), limits.max_bytes));
  const MeshFormat format = DetectMeshFormat(bytes);
  Result<ImportedMesh> read = NotComputed();
  // The readers call tinygltf, nlohmann-json and Draco, which may throw (bad
  // allocation included): an exception is a rejected input, never a crash.
  try {
    switch (format) {
      case MeshFormat::kObj:
        read = meshio::ReadObj(bytes, limits);
        break;
      case MeshFormat::kPly:
        read = meshio::ReadPly(bytes, limits);
        break;
      case MeshFormat::kStl:
        read = meshio::ReadStl(bytes, limits);
        break;
      case MeshFormat::kOff:
        read = meshio::ReadOff(bytes, limits);
        break;
      case MeshFormat::kDraco:
        read = meshio::ReadDraco(bytes, limits);
        break;
      case MeshFormat::kGlb:
      case MeshFormat::kGltf:
        read = meshio::ReadGltf(bytes, format == MeshFormat::kGlb, limits);
        break;
      case MeshFormat::kUnknown:
      case MeshFormat::k3mf:  // never detected: written only
        return Status(ErrorCode::kUnsupportedFormat,
                      "the bytes are in no supported mesh format (glTF/GLB, Draco, OBJ, PLY, STL, "
                      "OFF)",
                      "mesh");
    }
  } catch (const std::bad_alloc&) {
    return Status(ErrorCode::kLimitExceeded, "the mesh needs more memory than is available",
                  "mesh");
  } catch (const std::exception&) {
    return InvalidArgument(
        std::string("the ") + MeshFormatName(format) + " data could not be read (malformed)",
        "mesh");
  }
  SURFDEFORM_ASSIGN_OR_RETURN(ImportedMesh out, std::move(read));
  out.format = format;
  for (std::string& m : out.materials) m = meshio::CleanName(m);
  for (MeshGroup& g : out.mesh.groups) g.name = meshio::CleanName(g.name);
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
  if (const long long k = FirstNonFinite(out.mesh.positions); k >= 0) {
    return InvalidArgument("vertex " + std::to_string(k) + " has a non-finite position", "mesh");
  }
  return out;
}

}  // namespace surfdeform
