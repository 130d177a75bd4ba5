#include "engine/deform/rigid_parts.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace surfdeform {
namespace {

using Mat3 = Eigen::Matrix3d;

struct UnionFind {
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int Find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void Join(int a, int b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<int> parent;
};

// A position's bits, for welding equal positions (0.0 and -0.0 alike).
struct PositionKey {
  double x, y, z;
  bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PositionHash {
  size_t operator()(const PositionKey& k) const {
    size_t h = 0;
    for (double v : {k.x, k.y, k.z}) {
      v += 0.0;  // -0.0 -> 0.0
      uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      h = (h ^ bits) * 0x100000001b3ull;
    }
    return h;
  }
};

// Renumbers labels to 0 .. count - 1 in order of first appearance.
std::vector<int> Compact(const std::vector<int>& label, int* count) {
  std::unordered_map<int, int> id;
  std::vector<int> out(label.size());
  for (size_t k = 0; k < label.size(); ++k) {
    const auto [it, added] = id.emplace(label[k], static_cast<int>(id.size()));
    out[k] = it->second;
  }
  *count = static_cast<int>(id.size());
  return out;
}

}  // namespace

std::vector<int> RigidParts(const Mesh& mesh, RigidMode mode, int* count) {
  const size_t n = mesh.positions.size();
  std::vector<int> label(n);
  if (mode == RigidMode::kNone) {
    std::iota(label.begin(), label.end(), 0);
    *count = static_cast<int>(n);
    return label;
  }
  if (mode == RigidMode::kGroups) {
    // Labels: the group's input unit (its part, a glTF node or an OBJ g
    // group) when it has one, else the group itself (past every part id).
    int past = 0;
    for (const MeshGroup& g : mesh.groups) past = std::max(past, g.part + 1);
    std::fill(label.begin(), label.end(), -1);
    for (size_t g = 0; g < mesh.groups.size(); ++g) {
      const MeshGroup& group = mesh.groups[g];
      const int unit = group.part >= 0 ? group.part : past + static_cast<int>(g);
      for (uint32_t t = group.first_triangle; t < group.first_triangle + group.triangle_count; ++t)
        for (uint32_t v : mesh.triangles[t])
          if (label[v] < 0) label[v] = unit;
    }
    for (int& l : label) l = std::max(l, 0);
    return Compact(label, count);
  }
  UnionFind sets(n);
  std::unordered_map<PositionKey, int, PositionHash> first;
  for (size_t k = 0; k < n; ++k) {
    const Vec3& p = mesh.positions[k];
    const auto [it, added] = first.emplace(PositionKey{p.x(), p.y(), p.z()}, static_cast<int>(k));
    if (!added) sets.Join(it->second, static_cast<int>(k));
  }
  for (const auto& t : mesh.triangles) {
    sets.Join(static_cast<int>(t[0]), static_cast<int>(t[1]));
    sets.Join(static_cast<int>(t[0]), static_cast<int>(t[2]));
  }
  for (size_t k = 0; k < n; ++k) label[k] = sets.Find(static_cast<int>(k));
  return Compact(label, count);
}

RigidStats PlaceRigidParts(const SheetMap& map, const Placement& pl, const Mesh& in,
                           const std::vector<int>& part, int parts, OutsideMode outside,
                           Mesh* out) {
  const size_t n = in.positions.size();
  RigidStats st;
  st.parts = static_cast<size_t>(parts);
  st.each.resize(parts);
  // Placed coordinates and each part's footprint box.
  std::vector<Vec3> placed(n);
  std::vector<Eigen::AlignedBox2d> box(parts);
  for (size_t k = 0; k < n; ++k) {
    placed[k] = pl.Apply(in.positions[k]);
    box[part[k]].extend(placed[k].head<2>());
    ++st.each[part[k]].vertices;
  }
  // Each part's frame: origin S(c), axes the sheet's frame at c and N.
  const OutsideMode mode = outside == OutsideMode::kError ? OutsideMode::kExtrapolate : outside;
  std::vector<Vec3> origin(parts);
  std::vector<Mat3> frame(parts);
  std::vector<Vec2> centre(parts);
  for (int p = 0; p < parts; ++p) {
    centre[p] = box[p].center();
    const SheetParameters sp = map.Parameters(centre[p], mode, true, nullptr);
    if (sp.outside) {
      ++st.outside;
      st.each[p].outside = true;
      st.max_outside_distance = std::max(st.max_outside_distance, sp.outside_distance);
    }
    const SurfacePoint s = map.surface().Evaluate(sp.uv.x(), sp.uv.y(), 1);
    const Vec3 normal = UnitNormal(s);
    // The images of the sheet's a and b directions, made orthonormal in the
    // tangent plane (Gram-Schmidt), and the normal.
    const Vec3 da = s.su * sp.duv(0, 0) + s.sv * sp.duv(1, 0);
    const Vec3 db = s.su * sp.duv(0, 1) + s.sv * sp.duv(1, 1);
    const Vec3 t1 = (da - normal * normal.dot(da)).normalized();
    const Vec3 t2 = (db - normal * normal.dot(db) - t1 * t1.dot(db)).normalized();
    origin[p] = s.p;
    frame[p].col(0) = t1;
    frame[p].col(1) = t2;
    frame[p].col(2) = normal;
  }
  // Vertices: origin + frame (placed - c); normals and tangents rotated with
  // the whole placement's linear part (its inverse transpose for normals).
  const Mat3 linear = pl.Linear();
  const Mat3 normal_linear = linear.inverse().transpose();
  for (size_t k = 0; k < n; ++k) {
    const int p = part[k];
    const Vec3 local(placed[k].x() - centre[p].x(), placed[k].y() - centre[p].y(), placed[k].z());
    out->positions[k] = origin[p] + frame[p] * local;
    if (!in.normals.empty())
      out->normals[k] = (frame[p] * (normal_linear * in.normals[k])).normalized();
    if (!in.tangents.empty()) {
      const Vec3 t = (frame[p] * (linear * in.tangents[k].head<3>())).normalized();
      const double w =
          (frame[p] * linear).determinant() < 0.0 ? -in.tangents[k].w() : in.tangents[k].w();
      out->tangents[k] = Vec4(t.x(), t.y(), t.z(), w);
    }
  }
  // The footprint box's corners against the surface under them.
  for (int p = 0; p < parts; ++p) {
    RigidPartStats& e = st.each[p];
    const Eigen::AlignedBox2d& b = box[p];
    for (const Vec2& corner :
         {b.min(), b.max(), Vec2(b.min().x(), b.max().y()), Vec2(b.max().x(), b.min().y())}) {
      Vec3 surface, normal;
      map.SurfaceAndNormal(corner, mode, nullptr, &surface, &normal);
      const Vec2 d = corner - centre[p];
      const Vec3 rigid = origin[p] + frame[p] * Vec3(d.x(), d.y(), 0.0);
      const double gap = (rigid - surface).dot(normal);
      e.lift = std::max(e.lift, gap);
      e.sink = std::max(e.sink, -gap);
    }
    st.max_lift = std::max(st.max_lift, e.lift);
    st.max_sink = std::max(st.max_sink, e.sink);
  }
  return st;
}

}  // namespace surfdeform
