// STL (binary and ascii; coincident corners welded so that the mesh is
// connected) and OFF (OFF and COFF; faces of any size).
#include <cstring>
#include <unordered_map>

#include "meshio/importers.hpp"
#include "meshio/text_reader.hpp"

namespace surfdeform::meshio {
namespace {

struct PositionHash {
  size_t operator()(const std::array<double, 3>& p) const {
    size_t h = 0;
    for (double c : p) {
      uint64_t bits;
      std::memcpy(&bits, &c, 8);
      h = h * 1000003u ^ std::hash<uint64_t>()(bits);
    }
    return h;
  }
};

// Adds the triangle of three corners, sharing identical corners.
class Welder {
 public:
  explicit Welder(Mesh* mesh) : mesh_(mesh) {}
  void AddTriangle(const Vec3 corners[3]) {
    std::array<uint32_t, 3> t;
    for (int k = 0; k < 3; ++k) {
      const std::array<double, 3> key{corners[k].x(), corners[k].y(), corners[k].z()};
      auto [it, added] = index_.try_emplace(key, static_cast<uint32_t>(mesh_->positions.size()));
      if (added) mesh_->positions.push_back(corners[k]);
      t[k] = it->second;
    }
    mesh_->triangles.push_back(t);
  }

 private:
  Mesh* mesh_;
  std::unordered_map<std::array<double, 3>, uint32_t, PositionHash> index_;
};

Status ReadBinaryStl(std::string_view bytes, const ImportLimits& limits, Mesh* mesh) {
  uint32_t count;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (bytes.size() != 84 + 50ull * count) {
    return InvalidArgument("STL: the header claims " + std::to_string(count) +
                               " triangles, which do not match the file's size",
                           "mesh");
  }
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("triangles", count, limits.max_triangles));
  mesh->triangles.reserve(count);
  Welder welder(mesh);
  for (uint32_t t = 0; t < count; ++t) {
    const char* rec = bytes.data() + 84 + 50ull * t + 12;  // skip the facet normal
    Vec3 corners[3];
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 * k, 12);
      corners[k] = Vec3(xyz[0], xyz[1], xyz[2]);
    }
    welder.AddTriangle(corners);
  }
  return Status::Ok();
}

Status ReadAsciiStl(std::string_view bytes, const ImportLimits& limits, Mesh* mesh) {
  TextReader reader(bytes);
  std::string_view line, tok;
  Welder welder(mesh);
  Vec3 corners[3];
  int in_facet = 0;
  while (reader.NextLine(&line)) {
    const int ln = reader.line_number();
    if (!NextToken(&line, &tok)) continue;
    if (tok == "facet") {
      in_facet = 0;
    } else if (tok == "vertex") {
      if (in_facet == 3) return LineError(ln, "a facet has more than 3 vertices");
      double x[3];
      for (double& c : x) {
        if (!NextToken(&line, &tok) || !ParseNumber(tok, &c)) {
          return LineError(ln, "a vertex needs three numbers");
        }
      }
      corners[in_facet++] = Vec3(x[0], x[1], x[2]);
    } else if (tok == "endfacet") {
      if (in_facet != 3) return LineError(ln, "a facet needs 3 vertices");
      welder.AddTriangle(corners);
      SURFDEFORM_RETURN_IF_ERROR(
          CheckLimit("triangles", mesh->triangles.size(), limits.max_triangles));
      in_facet = 0;
    }
  }
  return Status::Ok();
}

}  // namespace

Result<ImportedMesh> ReadStl(std::string_view bytes, const ImportLimits& limits) {
  ImportedMesh out;
  const bool binary = bytes.size() >= 84 && DetectMeshFormat(bytes) == MeshFormat::kStl && [&] {
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    return bytes.size() == 84 + 50ull * count;
  }();
  SURFDEFORM_RETURN_IF_ERROR(binary ? ReadBinaryStl(bytes, limits, &out.mesh)
                                    : ReadAsciiStl(bytes, limits, &out.mesh));
  return out;
}

Result<ImportedMesh> ReadOff(std::string_view bytes, const ImportLimits& limits) {
  ImportedMesh out;
  TextReader reader(bytes);
  std::string_view line, tok;
  // Tokens across lines, comments skipped.
  auto next = [&](std::string_view* t) {
    while (!NextToken(&line, t) || t->front() == '#') {
      if (!reader.NextLine(&line)) return false;
    }
    return true;
  };
  if (!next(&tok)) return InvalidArgument("OFF: empty file", "mesh");
  const bool colored = tok == "COFF" || tok == "CNOFF";
  const bool normals = tok == "NOFF" || tok == "CNOFF";
  int64_t counts[3];
  for (int64_t& c : counts) {
    if (!next(&tok) || !ParseNumber(tok, &c) || c < 0) {
      return InvalidArgument("OFF: the header needs vertex, face and edge counts", "mesh");
    }
  }
  const size_t nv = static_cast<size_t>(counts[0]), nf = static_cast<size_t>(counts[1]);
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("vertices", nv, limits.max_vertices));
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("faces", nf, limits.max_triangles));
  // At least 6 characters a vertex ("0 0 0\n") and 8 a face: reject counts the
  // file cannot hold before allocating.
  if (nv > bytes.size() / 6 || nf > bytes.size() / 8) {
    return InvalidArgument("OFF: the header claims more vertices or faces than the file holds",
                           "mesh");
  }
  Mesh& mesh = out.mesh;
  mesh.positions.resize(nv);
  if (colored) mesh.colors.resize(nv);
  const int per_vertex = 3 + (normals ? 3 : 0) + (colored ? 4 : 0);
  for (size_t v = 0; v < nv; ++v) {
    double x[10];
    for (int k = 0; k < per_vertex; ++k) {
      if (!next(&tok) || !ParseNumber(tok, &x[k])) {
        return LineError(reader.line_number(), "bad vertex " + std::to_string(v));
      }
    }
    mesh.positions[v] = Vec3(x[0], x[1], x[2]);
    if (colored) {
      const double* c = x + (normals ? 6 : 3);
      const bool bytes_colour = c[0] > 1 || c[1] > 1 || c[2] > 1 || c[3] > 1;
      mesh.colors[v] = Vec4(c[0], c[1], c[2], c[3]) / (bytes_colour ? 255.0 : 1.0);
    }
  }
  uint32_t poly[256];
  for (size_t f = 0; f < nf; ++f) {
    int64_t n;
    if (!next(&tok) || !ParseNumber(tok, &n) || n < 3 || n > 256) {
      return LineError(reader.line_number(),
                       "face " + std::to_string(f) + " needs a corner count from 3 to 256");
    }
    for (int64_t k = 0; k < n; ++k) {
      int64_t idx;
      if (!next(&tok) || !ParseNumber(tok, &idx) || idx < 0 || idx >= counts[0]) {
        return LineError(reader.line_number(),
                         "face " + std::to_string(f) + " has a vertex index out of range");
      }
      poly[k] = static_cast<uint32_t>(idx);
    }
    Vec3 corner_positions[256];
    for (int64_t k = 0; k < n; ++k) corner_positions[k] = mesh.positions[poly[k]];
    AppendPolygon(poly, corner_positions, static_cast<size_t>(n), &mesh);
    line = {};  // a face line may end with a colour: skip the rest of it
  }
  return out;
}

}  // namespace surfdeform::meshio
