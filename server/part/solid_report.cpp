#include "part/solid_report.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <unordered_map>

#include "base/format.hpp"

namespace surfdeform {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<Kernel::Point_3>;

constexpr size_t kBordersNamed = 5;

bool SelfIntersects(const Mesh& mesh) {
  CgalMesh m;
  m.reserve(static_cast<CgalMesh::size_type>(mesh.positions.size()),
            static_cast<CgalMesh::size_type>(3 * mesh.triangles.size() / 2),
            static_cast<CgalMesh::size_type>(mesh.triangles.size()));
  std::vector<CgalMesh::Vertex_index> vertex;
  vertex.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) vertex.push_back(m.add_vertex({p.x(), p.y(), p.z()}));
  for (const auto& t : mesh.triangles) {
    if (m.add_face(vertex[t[0]], vertex[t[1]], vertex[t[2]]) == CgalMesh::null_face()) {
      return true;  // not a valid halfedge structure: treated as crossing
    }
  }
  return CGAL::Polygon_mesh_processing::does_self_intersect(m);
}

}  // namespace

SolidReport CheckSolid(const Mesh& mesh, bool self_intersections) {
  SolidReport r;
  r.vertices = mesh.positions.size();
  r.triangles = mesh.triangles.size();
  if (!mesh.positions.empty()) {
    r.lo = r.hi = mesh.positions.front();
    for (const Vec3& p : mesh.positions) {
      r.lo = r.lo.cwiseMin(p);
      r.hi = r.hi.cwiseMax(p);
    }
  }
  const double diagonal = (r.hi - r.lo).norm();
  // Each undirected edge: how many triangles run it each way.
  struct Uses {
    uint32_t forward = 0, backward = 0;
  };
  std::unordered_map<uint64_t, Uses> edges;
  edges.reserve(3 * mesh.triangles.size() / 2);
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.positions[t[0]];
    const Vec3& b = mesh.positions[t[1]];
    const Vec3& c = mesh.positions[t[2]];
    const Vec3 cross = (b - a).cross(c - a);
    r.area += cross.norm() / 2;
    r.volume += a.dot(b.cross(c)) / 6;
    if (cross.norm() <= 1e-14 * diagonal * diagonal || t[0] == t[1] || t[1] == t[2] ||
        t[0] == t[2]) {
      ++r.degenerate_triangles;
    }
    for (int e = 0; e < 3; ++e) {
      const uint32_t x = t[e], y = t[(e + 1) % 3];
      const uint64_t key = (static_cast<uint64_t>(std::min(x, y)) << 32) | std::max(x, y);
      Uses& u = edges[key];
      (x < y ? u.forward : u.backward) += 1;
    }
  }
  for (const auto& [key, u] : edges) {
    const uint32_t n = u.forward + u.backward;
    if (n == 1) {
      if (r.border_at.size() < kBordersNamed) {
        const Vec3& p = mesh.positions[static_cast<uint32_t>(key >> 32)];
        const Vec3& q = mesh.positions[static_cast<uint32_t>(key & 0xffffffffu)];
        r.border_at.push_back((p + q) / 2);
      }
      ++r.border_edges;
    } else if (n > 2) {
      ++r.non_manifold_edges;
    } else if (u.forward != 1) {
      ++r.misoriented_edges;
    }
  }
  // The list above runs in the hash map's order: name the first borders by
  // position instead, so that the same mesh names the same places.
  std::sort(r.border_at.begin(), r.border_at.end(), [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  if (self_intersections && r.closed() && r.degenerate_triangles == 0) {
    r.self_intersection_checked = true;
    r.self_intersects = SelfIntersects(mesh);
  }
  return r;
}

Status SolidProblem(const SolidReport& r, const std::string& what, const std::string& field) {
  if (!r.closed()) {
    std::string where;
    for (const Vec3& p : r.border_at) {
      where += Format("%s(%.4g, %.4g, %.4g)", where.empty() ? "" : ", ", p.x(), p.y(), p.z());
    }
    if (r.border_edges > 0) {
      return Status(ErrorCode::kDegenerate,
                    Format("%s is not closed: %zu edges border one triangle only (near %s); a "
                           "solid's every edge is shared by two",
                           what.c_str(), r.border_edges, where.c_str()),
                    field)
          .WithLimit(0, static_cast<double>(r.border_edges));
    }
    return Status(ErrorCode::kDegenerate,
                  Format("%s is not a manifold: %zu edges are shared by three triangles or more",
                         what.c_str(), r.non_manifold_edges),
                  field)
        .WithLimit(0, static_cast<double>(r.non_manifold_edges));
  }
  if (!r.oriented()) {
    return Status(ErrorCode::kDegenerate,
                  Format("%s is not consistently oriented: %zu edges are run the same way by "
                         "both their triangles",
                         what.c_str(), r.misoriented_edges),
                  field)
        .WithLimit(0, static_cast<double>(r.misoriented_edges));
  }
  if (r.degenerate_triangles > 0) {
    return Status(ErrorCode::kDegenerate,
                  Format("%s has %zu degenerate triangles (no area)", what.c_str(),
                         r.degenerate_triangles),
                  field)
        .WithLimit(0, static_cast<double>(r.degenerate_triangles));
  }
  if (r.self_intersects) {
    return Status(ErrorCode::kDegenerate,
                  Format("%s intersects itself: its triangles cross one another", what.c_str()),
                  field);
  }
  if (!(r.volume > 0)) {
    return Status(ErrorCode::kDegenerate,
                  Format("%s bounds no volume (%.4g mm^3): its triangles face inward", what.c_str(),
                         r.volume),
                  field);
  }
  return Status();
}

}  // namespace surfdeform
