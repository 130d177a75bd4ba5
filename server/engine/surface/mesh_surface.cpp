#include "engine/surface/mesh_surface.hpp"

#include <algorithm>
#include <limits>

namespace surfdeform {

FlatTriangles IndexFlatMesh(const FlatMesh& mesh) {
  const DiskMesh& m = mesh.mesh;
  // The triangle on each boundary edge: the one with that edge unpaired.
  const size_t nb = m.boundary.size();
  std::vector<int> on_edge(nb, -1);
  std::vector<int> position(m.positions.size(), -1);
  for (size_t k = 0; k < nb; ++k) position[m.boundary[k]] = static_cast<int>(k);
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (m.neighbours[f][c] >= 0) continue;
      const int k = position[m.triangles[f][c]];
      if (k >= 0) on_edge[k] = static_cast<int>(f);
    }
  }
  return FlatTriangles(mesh.flat, m.triangles, m.boundary, on_edge);
}

MeshSurface::MeshSurface(std::shared_ptr<const FlatMesh> mesh)
    : mesh_(std::move(mesh)), index_(IndexFlatMesh(*mesh_)) {
  // The box's centre: the area centroid (the canonical frame's origin), or
  // the triangle centre nearest it.
  Vec2 centre = Vec2::Zero();
  Vec3 bary;
  if (index_.Locate(centre, &bary) < 0) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : mesh_->mesh.triangles) {
      const Vec2 c = (mesh_->flat[t[0]] + mesh_->flat[t[1]] + mesh_->flat[t[2]]) / 3.0;
      if (c.norm() < best) {
        best = c.norm();
        centre = c;
      }
    }
  }
  const Eigen::AlignedBox2d& b = index_.bounds();
  const Vec2 half = (b.max() - centre).cwiseMax(centre - b.min()).cwiseMax(1e-300);
  box_min_ = centre - half;
  box_size_ = 2.0 * half;
}

std::optional<double> MeshSurface::DomainGap(const Vec2& uv, Vec2* nearest) const {
  const Vec2 p = *ExactUnrolling(uv.x(), uv.y());
  Vec3 bary;
  if (index_.Locate(p, &bary) >= 0) {
    if (nearest != nullptr) *nearest = uv;
    return 0.0;
  }
  const FlatTriangles::Nearest n = index_.NearestOnBoundary(p);
  if (nearest != nullptr) *nearest = *InverseUnrolling(n.point);
  return n.distance;
}

std::optional<double> MeshSurface::DomainDepth(const Vec2& uv) const {
  const Vec2 p = *ExactUnrolling(uv.x(), uv.y());
  Vec3 bary;
  const double d = index_.NearestOnBoundary(p).distance;
  return index_.Locate(p, &bary) >= 0 ? d : -d;
}

SurfacePoint MeshSurface::Evaluate(double u, double v, int order) const {
  const Vec2 p = *ExactUnrolling(u, v);
  Vec3 bary;
  int f = index_.Locate(p, &bary);
  Vec3 normal_bary;
  if (f >= 0) {
    normal_bary = bary;
  } else {
    // Off the mesh: continue the nearest boundary triangle's plane; the
    // normal is the one at the nearest boundary point.
    const FlatTriangles::Nearest n = index_.NearestOnBoundary(p);
    f = n.triangle;
    bary = index_.Barycentric(f, p);
    normal_bary = index_.Barycentric(f, n.point).cwiseMax(0.0);
    normal_bary /= normal_bary.sum();
  }
  const auto& t = mesh_->mesh.triangles[f];
  const std::vector<Vec3>& x = mesh_->mesh.positions;
  SurfacePoint s;
  s.p = bary(0) * x[t[0]] + bary(1) * x[t[1]] + bary(2) * x[t[2]];
  if (order < 1) return s;
  const std::vector<Vec3>& nv = mesh_->normals;
  Vec3 normal = normal_bary(0) * nv[t[0]] + normal_bary(1) * nv[t[1]] + normal_bary(2) * nv[t[2]];
  const Vec3 facet = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
  if (!(normal.dot(facet) > 0.0)) normal = facet;  // opposed vertex normals: the facet's
  normal.normalize();
  // d(position)/d(flat): the triangle's affine map.
  Eigen::Matrix2d flat;
  flat.col(0) = mesh_->flat[t[1]] - mesh_->flat[t[0]];
  flat.col(1) = mesh_->flat[t[2]] - mesh_->flat[t[0]];
  Eigen::Matrix<double, 3, 2> space;
  space.col(0) = x[t[1]] - x[t[0]];
  space.col(1) = x[t[2]] - x[t[0]];
  const Eigen::Matrix<double, 3, 2> a = space * flat.inverse();
  const Vec3 su = a.col(0) * box_size_.x();
  const Vec3 sv = a.col(1) * box_size_.y();
  s.su = su - normal * normal.dot(su);
  s.sv = sv - normal * normal.dot(sv);
  return s;
}

}  // namespace surfdeform
