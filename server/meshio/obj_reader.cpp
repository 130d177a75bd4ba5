// Wavefront OBJ: v (with optional r g b), vt, vn, f (any polygon, negative
// indices relative), usemtl groups; l and p elements are reported and ignored.
#include <array>
#include <unordered_map>

#include "meshio/importers.hpp"
#include "meshio/text_reader.hpp"

namespace surfdeform::meshio {
namespace {

// What the file defines, read a line at a time: vertices, texture
// coordinates and normals as given; faces as the output's triangles over
// output vertices, one per distinct (v, vt, vn) corner; materials and groups
// as runs of triangles.
class ObjParser {
 public:
  explicit ObjParser(const ImportLimits& limits) : limits_(limits) {}

  // One line, its first token already taken (`tok`), the rest in `line`.
  Status Line(std::string_view tok, std::string_view line, int ln) {
    if (tok == "v") return Vertex(line, ln);
    if (tok == "vt") return TexCoord(line, ln);
    if (tok == "vn") return Normal(line, ln);
    if (tok == "f") return Face(line, ln);
    if (tok == "usemtl") return UseMaterial(Trimmed(line));
    if (tok == "g" || tok == "o") {
      // A new group of the file: a new run (same material), its own part.
      ++current_part_;
      return StartGroup(current_material_, Trimmed(line));
    }
    if (tok == "l") {
      ++ignored_lines_;
    } else if (tok == "p") {
      ++ignored_points_;
    }
    return Status::Ok();
  }

  // The mesh, once every line is read.
  ImportedMesh Finish() && {
    Mesh& mesh = out_.mesh;
    if (!mesh.groups.empty() && mesh.groups.back().triangle_count == 0) mesh.groups.pop_back();
    KeepTheFilesVertexOrder();
    Assemble();
    AddWarnings();
    return std::move(out_);
  }

 private:
  struct CornerKey {
    int64_t v, t, n;
    bool operator==(const CornerKey&) const = default;
  };
  struct CornerHash {
    size_t operator()(const CornerKey& k) const {
      return std::hash<int64_t>()(k.v * 1000003 + k.t * 7919 + k.n);
    }
  };

  static std::string Trimmed(std::string_view line) {
    std::string name(line);
    while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.erase(0, 1);
    return name;
  }

  Status Vertex(std::string_view line, int ln) {
    std::string_view tok;
    double x[7];
    int count = 0;
    while (count < 7 && NextToken(&line, &tok)) {
      if (!ParseNumber(tok, &x[count])) return LineError(ln, "bad number in a vertex");
      ++count;
    }
    if (count < 3) return LineError(ln, "a vertex needs x y z");
    v_.emplace_back(x[0], x[1], x[2]);
    if (count >= 6) {
      colors_.resize(v_.size() - 1, Vec4(1, 1, 1, 1));
      colors_.emplace_back(x[3], x[4], x[5], 1.0);
    }
    return CheckLimit("vertices", v_.size(), limits_.max_vertices);
  }

  Status TexCoord(std::string_view line, int ln) {
    std::string_view tok;
    double x[2] = {0, 0};
    for (int k = 0; k < 2 && NextToken(&line, &tok); ++k) {
      if (!ParseNumber(tok, &x[k])) return LineError(ln, "bad number in a texture coordinate");
    }
    vt_.emplace_back(x[0], x[1]);
    return Status::Ok();
  }

  Status Normal(std::string_view line, int ln) {
    std::string_view tok;
    double x[3];
    for (double& c : x) {
      if (!NextToken(&line, &tok) || !ParseNumber(tok, &c)) {
        return LineError(ln, "a normal needs three numbers");
      }
    }
    vn_.emplace_back(x[0], x[1], x[2]);
    return Status::Ok();
  }

  // A face corner "v", "v/vt", "v//vn" or "v/vt/vn" (negative: relative),
  // resolved against what is defined so far.
  Result<CornerKey> Corner(std::string_view tok, int ln) const {
    int64_t idx[3] = {0, 0, 0};
    const size_t sizes[3] = {v_.size(), vt_.size(), vn_.size()};
    const char* names[3] = {"vertex", "texture coordinate", "normal"};
    for (int part = 0; part < 3; ++part) {
      const size_t slash = tok.find('/');
      const std::string_view field = tok.substr(0, slash);
      if (!field.empty()) {
        if (!ParseNumber(field, &idx[part])) return LineError(ln, "bad index in a face");
        const int64_t resolved =
            idx[part] < 0 ? static_cast<int64_t>(sizes[part]) + idx[part] : idx[part] - 1;
        if (idx[part] == 0 || resolved < 0 || resolved >= static_cast<int64_t>(sizes[part])) {
          return LineError(ln, std::string(names[part]) + " index " + std::to_string(idx[part]) +
                                   " is out of range (" + std::to_string(sizes[part]) +
                                   " defined so far)");
        }
        idx[part] = resolved + 1;
      } else if (part == 0) {
        return LineError(ln, "a face corner needs a vertex index");
      }
      if (slash == std::string_view::npos) break;
      tok.remove_prefix(slash + 1);
    }
    return CornerKey{idx[0] - 1, idx[1] - 1, idx[2] - 1};
  }

  Status Face(std::string_view line, int ln) {
    Mesh& mesh = out_.mesh;
    std::string_view tok;
    std::array<uint32_t, kMaxPolygon> poly;
    size_t n = 0;
    while (NextToken(&line, &tok)) {
      if (n == kMaxPolygon) {
        return LineError(ln, "a face has more than " + std::to_string(kMaxPolygon) + " corners");
      }
      SURFDEFORM_ASSIGN_OR_RETURN(const CornerKey key, Corner(tok, ln));
      any_uv_ |= key.t >= 0;
      missing_uv_ |= key.t < 0;
      any_normal_ |= key.n >= 0;
      missing_normal_ |= key.n < 0;
      auto [it, added] = corners_.try_emplace(key, static_cast<uint32_t>(vertex_keys_.size()));
      if (added) {
        vertex_keys_.push_back(key);
        SURFDEFORM_RETURN_IF_ERROR(
            CheckLimit("vertices", vertex_keys_.size(), limits_.max_vertices));
      }
      poly[n++] = it->second;
    }
    if (n < 3) return LineError(ln, "a face needs at least 3 corners");
    if (mesh.groups.empty()) SURFDEFORM_RETURN_IF_ERROR(StartGroup(current_material_, ""));
    std::array<Vec3, kMaxPolygon> corner_positions;
    for (size_t k = 0; k < n; ++k) corner_positions[k] = v_[vertex_keys_[poly[k]].v];
    AppendPolygon(poly.data(), corner_positions.data(), n, &mesh);
    mesh.groups.back().triangle_count =
        static_cast<uint32_t>(mesh.triangles.size()) - mesh.groups.back().first_triangle;
    return CheckLimit("triangles", mesh.triangles.size(), limits_.max_triangles);
  }

  // A material by name (found in a hash map: a file may name very many).
  Status UseMaterial(const std::string& name) {
    auto [it, added] = material_index_.emplace(name, static_cast<int>(out_.materials.size()));
    if (added) out_.materials.push_back(name);
    current_material_ = it->second;
    return StartGroup(current_material_, name);
  }

  Status StartGroup(int material, const std::string& name) {
    Mesh& mesh = out_.mesh;
    if (!mesh.groups.empty() && mesh.groups.back().triangle_count == 0) mesh.groups.pop_back();
    MeshGroup g;
    g.name = name;
    g.material = material;
    g.part = current_part_;
    g.first_triangle = static_cast<uint32_t>(mesh.triangles.size());
    mesh.groups.push_back(g);
    return CheckLimit("groups (runs of one material or g/o group)", mesh.groups.size(),
                      limits_.max_groups);
  }

  // When every corner uses the same index for v, vt and vn (or leaves them
  // out consistently), the file's own vertex order and count are kept:
  // deformed frames written as OBJ stay usable as morph targets.
  void KeepTheFilesVertexOrder() {
    bool aligned = true;
    for (const CornerKey& key : vertex_keys_) {
      aligned &= (key.t < 0 || key.t == key.v) && (key.n < 0 || key.n == key.v) &&
                 (key.t >= 0) == any_uv_ && (key.n >= 0) == any_normal_;
    }
    if (!aligned || vertex_keys_.empty()) return;
    std::vector<CornerKey> by_vertex(v_.size(), CornerKey{-1, -1, -1});
    for (const CornerKey& key : vertex_keys_) by_vertex[key.v] = key;
    for (size_t k = 0; k < v_.size(); ++k) {
      if (by_vertex[k].v < 0)
        by_vertex[k] = {static_cast<int64_t>(k), any_uv_ ? static_cast<int64_t>(k) : -1,
                        any_normal_ ? static_cast<int64_t>(k) : -1};
    }
    if ((any_uv_ && vt_.size() < v_.size()) || (any_normal_ && vn_.size() < v_.size())) return;
    for (auto& t : out_.mesh.triangles)
      for (uint32_t& c : t) c = static_cast<uint32_t>(vertex_keys_[c].v);
    vertex_keys_ = std::move(by_vertex);
  }

  // The output vertices' attributes from their corners.
  void Assemble() {
    Mesh& mesh = out_.mesh;
    const size_t n = vertex_keys_.size();
    mesh.positions.resize(n);
    if (any_uv_) mesh.uv0.assign(n, Vec2::Zero());
    if (any_normal_) mesh.normals.assign(n, Vec3::UnitZ());
    if (!colors_.empty()) {
      colors_.resize(v_.size(), Vec4(1, 1, 1, 1));
      mesh.colors.resize(n);
    }
    for (size_t k = 0; k < n; ++k) {
      const CornerKey& key = vertex_keys_[k];
      mesh.positions[k] = v_[key.v];
      if (any_uv_ && key.t >= 0) mesh.uv0[k] = vt_[key.t];
      if (any_normal_ && key.n >= 0) {
        const double len = vn_[key.n].norm();
        mesh.normals[k] = len > 0.0 ? Vec3(vn_[key.n] / len) : Vec3::UnitZ();
      }
      if (!colors_.empty()) mesh.colors[k] = colors_[key.v];
    }
  }

  void AddWarnings() {
    std::vector<std::string>& w = out_.warnings;
    if (any_uv_ && missing_uv_) {
      w.push_back("some face corners have no texture coordinate: set to (0, 0)");
    }
    if (any_normal_ && missing_normal_) w.push_back("some face corners have no normal: set to +Z");
    if (ignored_lines_ > 0) {
      w.push_back("ignored " + std::to_string(ignored_lines_) + " line elements (l)");
    }
    if (ignored_points_ > 0) {
      w.push_back("ignored " + std::to_string(ignored_points_) + " point elements (p)");
    }
  }

  const ImportLimits& limits_;
  ImportedMesh out_;
  std::vector<Vec3> v_;
  std::vector<Vec4> colors_;
  std::vector<Vec2> vt_;
  std::vector<Vec3> vn_;
  std::unordered_map<CornerKey, uint32_t, CornerHash> corners_;
  std::vector<CornerKey> vertex_keys_;  // output vertex -> its corner
  std::unordered_map<std::string, int> material_index_;
  int current_material_ = -1;
  int current_part_ = -1;  // the g/o group (counted), for rigid parts
  size_t ignored_lines_ = 0, ignored_points_ = 0;
  bool any_uv_ = false, any_normal_ = false, missing_uv_ = false, missing_normal_ = false;
};

}  // namespace

Result<ImportedMesh> ReadObj(std::string_view bytes, const ImportLimits& limits) {
  ObjParser parser(limits);
  TextReader reader(bytes);
  std::string_view line, tok;
  while (reader.NextLine(&line)) {
    if (!NextToken(&line, &tok) || tok.front() == '#') continue;
    SURFDEFORM_RETURN_IF_ERROR(parser.Line(tok, line, reader.line_number()));
  }
  return std::move(parser).Finish();
}

}  // namespace surfdeform::meshio
