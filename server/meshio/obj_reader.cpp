// Wavefront OBJ: v (with optional r g b), vt, vn, f (any polygon, negative
// indices relative), usemtl groups; l and p elements are reported and ignored.
#include <array>
#include <unordered_map>

#include "meshio/importers.hpp"
#include "meshio/text_reader.hpp"

namespace surfdeform::meshio {
namespace {

constexpr size_t kMaxPolygon = 256;

struct CornerKey {
  int64_t v, t, n;
  bool operator==(const CornerKey&) const = default;
};
struct CornerHash {
  size_t operator()(const CornerKey& k) const {
    return std::hash<int64_t>()(k.v * 1000003 + k.t * 7919 + k.n);
  }
};

}  // namespace

Result<ImportedMesh> ReadObj(std::string_view bytes, const ImportLimits& limits) {
  ImportedMesh out;
  std::vector<Vec3> v;
  std::vector<Vec4> colors;
  std::vector<Vec2> vt;
  std::vector<Vec3> vn;
  std::unordered_map<CornerKey, uint32_t, CornerHash> corners;
  std::vector<CornerKey> vertex_keys;  // output vertex -> its corner
  Mesh& mesh = out.mesh;
  int current_material = -1;
  size_t ignored_lines = 0, ignored_points = 0;
  bool any_uv = false, any_normal = false, missing_uv = false, missing_normal = false;

  int current_part = -1;  // the g/o group (counted), for rigid parts
  auto start_group = [&](int material, const std::string& name) {
    if (!mesh.groups.empty() && mesh.groups.back().triangle_count == 0) mesh.groups.pop_back();
    MeshGroup g;
    g.name = name;
    g.material = material;
    g.part = current_part;
    g.first_triangle = static_cast<uint32_t>(mesh.triangles.size());
    mesh.groups.push_back(g);
  };

  TextReader reader(bytes);
  std::string_view line, tok;
  while (reader.NextLine(&line)) {
    const int ln = reader.line_number();
    if (!NextToken(&line, &tok) || tok.front() == '#') continue;
    if (tok == "v") {
      double x[7];
      int count = 0;
      while (count < 7 && NextToken(&line, &tok)) {
        if (!ParseNumber(tok, &x[count])) return LineError(ln, "bad number in a vertex");
        ++count;
      }
      if (count < 3) return LineError(ln, "a vertex needs x y z");
      v.emplace_back(x[0], x[1], x[2]);
      if (count >= 6) {
        colors.resize(v.size() - 1, Vec4(1, 1, 1, 1));
        colors.emplace_back(x[3], x[4], x[5], 1.0);
      }
      SURFDEFORM_RETURN_IF_ERROR(CheckLimit("vertices", v.size(), limits.max_vertices));
    } else if (tok == "vt") {
      double x[2] = {0, 0};
      for (int k = 0; k < 2 && NextToken(&line, &tok); ++k) {
        if (!ParseNumber(tok, &x[k])) return LineError(ln, "bad number in a texture coordinate");
      }
      vt.emplace_back(x[0], x[1]);
    } else if (tok == "vn") {
      double x[3];
      for (double& c : x) {
        if (!NextToken(&line, &tok) || !ParseNumber(tok, &c)) {
          return LineError(ln, "a normal needs three numbers");
        }
      }
      vn.emplace_back(x[0], x[1], x[2]);
    } else if (tok == "f") {
      std::array<uint32_t, kMaxPolygon> poly;
      size_t n = 0;
      while (NextToken(&line, &tok)) {
        if (n == kMaxPolygon) {
          return LineError(ln, "a face has more than " + std::to_string(kMaxPolygon) + " corners");
        }
        int64_t idx[3] = {0, 0, 0};
        const size_t sizes[3] = {v.size(), vt.size(), vn.size()};
        const char* names[3] = {"vertex", "texture coordinate", "normal"};
        for (int part = 0; part < 3; ++part) {
          const size_t slash = tok.find('/');
          const std::string_view field = tok.substr(0, slash);
          if (!field.empty()) {
            if (!ParseNumber(field, &idx[part])) return LineError(ln, "bad index in a face");
            const int64_t resolved =
                idx[part] < 0 ? static_cast<int64_t>(sizes[part]) + idx[part] : idx[part] - 1;
            if (idx[part] == 0 || resolved < 0 || resolved >= static_cast<int64_t>(sizes[part])) {
              return LineError(ln, std::string(names[part]) + " index " +
                                       std::to_string(idx[part]) + " is out of range (" +
                                       std::to_string(sizes[part]) + " defined so far)");
            }
            idx[part] = resolved + 1;
          } else if (part == 0) {
            return LineError(ln, "a face corner needs a vertex index");
          }
          if (slash == std::string_view::npos) break;
          tok.remove_prefix(slash + 1);
        }
        const CornerKey key{idx[0] - 1, idx[1] - 1, idx[2] - 1};
        any_uv |= key.t >= 0;
        missing_uv |= key.t < 0;
        any_normal |= key.n >= 0;
        missing_normal |= key.n < 0;
        auto [it, added] = corners.try_emplace(key, static_cast<uint32_t>(vertex_keys.size()));
        if (added) {
          vertex_keys.push_back(key);
          SURFDEFORM_RETURN_IF_ERROR(
              CheckLimit("vertices", vertex_keys.size(), limits.max_vertices));
        }
        poly[n++] = it->second;
      }
      if (n < 3) return LineError(ln, "a face needs at least 3 corners");
      if (mesh.groups.empty()) start_group(current_material, "");
      std::array<Vec3, kMaxPolygon> corner_positions;
      for (size_t k = 0; k < n; ++k) corner_positions[k] = v[vertex_keys[poly[k]].v];
      AppendPolygon(poly.data(), corner_positions.data(), n, &mesh);
      mesh.groups.back().triangle_count =
          static_cast<uint32_t>(mesh.triangles.size()) - mesh.groups.back().first_triangle;
      SURFDEFORM_RETURN_IF_ERROR(
          CheckLimit("triangles", mesh.triangles.size(), limits.max_triangles));
    } else if (tok == "usemtl") {
      std::string name(line);
      while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.erase(0, 1);
      int index = -1;
      for (size_t m = 0; m < out.materials.size(); ++m) {
        if (out.materials[m] == name) index = static_cast<int>(m);
      }
      if (index < 0) {
        index = static_cast<int>(out.materials.size());
        out.materials.push_back(name);
      }
      current_material = index;
      start_group(current_material, name);
    } else if (tok == "g" || tok == "o") {
      // A new group of the file: a new run (same material), its own part.
      ++current_part;
      std::string name(line);
      while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.erase(0, 1);
      start_group(current_material, name);
    } else if (tok == "l") {
      ++ignored_lines;
    } else if (tok == "p") {
      ++ignored_points;
    }
  }
  if (!mesh.groups.empty() && mesh.groups.back().triangle_count == 0) mesh.groups.pop_back();

  // When every corner uses the same index for v, vt and vn (or leaves them
  // out consistently), the file's own vertex order and count are kept:
  // deformed frames written as OBJ stay usable as morph targets.
  bool aligned = true;
  for (const CornerKey& key : vertex_keys) {
    aligned &= (key.t < 0 || key.t == key.v) && (key.n < 0 || key.n == key.v) &&
               (key.t >= 0) == any_uv && (key.n >= 0) == any_normal;
  }
  if (aligned && !vertex_keys.empty()) {
    std::vector<CornerKey> by_vertex(v.size(), CornerKey{-1, -1, -1});
    for (const CornerKey& key : vertex_keys) by_vertex[key.v] = key;
    for (size_t k = 0; k < v.size(); ++k) {
      if (by_vertex[k].v < 0)
        by_vertex[k] = {static_cast<int64_t>(k), any_uv ? static_cast<int64_t>(k) : -1,
                        any_normal ? static_cast<int64_t>(k) : -1};
    }
    aligned = (!any_uv || vt.size() >= v.size()) && (!any_normal || vn.size() >= v.size());
    if (aligned) {
      for (auto& t : mesh.triangles)
        for (uint32_t& c : t) c = static_cast<uint32_t>(vertex_keys[c].v);
      vertex_keys = std::move(by_vertex);
    }
  }
  const size_t n = vertex_keys.size();
  mesh.positions.resize(n);
  if (any_uv) mesh.uv0.assign(n, Vec2::Zero());
  if (any_normal) mesh.normals.assign(n, Vec3::UnitZ());
  if (!colors.empty()) {
    colors.resize(v.size(), Vec4(1, 1, 1, 1));
    mesh.colors.resize(n);
  }
  for (size_t k = 0; k < n; ++k) {
    const CornerKey& key = vertex_keys[k];
    mesh.positions[k] = v[key.v];
    if (any_uv && key.t >= 0) mesh.uv0[k] = vt[key.t];
    if (any_normal && key.n >= 0) {
      const double len = vn[key.n].norm();
      mesh.normals[k] = len > 0.0 ? Vec3(vn[key.n] / len) : Vec3::UnitZ();
    }
    if (!colors.empty()) mesh.colors[k] = colors[key.v];
  }
  if (any_uv && missing_uv)
    out.warnings.push_back("some face corners have no texture coordinate: set to (0, 0)");
  if (any_normal && missing_normal)
    out.warnings.push_back("some face corners have no normal: set to +Z");
  if (ignored_lines > 0) {
    out.warnings.push_back("ignored " + std::to_string(ignored_lines) + " line elements (l)");
  }
  if (ignored_points > 0) {
    out.warnings.push_back("ignored " + std::to_string(ignored_points) + " point elements (p)");
  }
  return out;
}

}  // namespace surfdeform::meshio
