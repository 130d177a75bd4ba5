#include "engine/surface/flat_triangles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace surfdeform {
namespace {

// The point of segment [a, b] nearest p.
Vec2 NearestOnSegment(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 e = b - a;
  const double ee = e.squaredNorm();
  const double t = ee > 0.0 ? std::clamp((p - a).dot(e) / ee, 0.0, 1.0) : 0.0;
  return a + t * e;
}

}  // namespace

FlatTriangles::FlatTriangles(const std::vector<Vec2>& flat,
                             const std::vector<std::array<int, 3>>& triangles,
                             const std::vector<int>& boundary,
                             const std::vector<int>& boundary_triangles) {
  const int nf = static_cast<int>(triangles.size());
  origin_.resize(nf);
  inverse_.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const auto& t = triangles[f];
    origin_[f] = flat[t[0]];
    Eigen::Matrix2d m;
    m.col(0) = flat[t[1]] - flat[t[0]];
    m.col(1) = flat[t[2]] - flat[t[0]];
    inverse_[f] = m.inverse();
  }
  const int nb = static_cast<int>(boundary.size());
  segments_.resize(nb);
  segment_triangle_ = boundary_triangles;
  for (int k = 0; k < nb; ++k) {
    segments_[k] = {flat[boundary[k]], flat[boundary[(k + 1) % nb]]};
  }
  Eigen::AlignedBox2d bounds;
  for (const Vec2& p : flat) bounds.extend(p);
  grid_ = UniformBuckets(bounds, nf);  // about one triangle per bucket
  grid_.Fill(
      nf,
      [&](int f) {
        Eigen::AlignedBox2d b;
        for (int v : triangles[f]) b.extend(flat[v]);
        return b;
      },
      &triangle_start_, &triangle_ids_);
  grid_.Fill(
      nb,
      [&](int k) {
        Eigen::AlignedBox2d b;
        b.extend(segments_[k][0]);
        b.extend(segments_[k][1]);
        return b;
      },
      &segment_start_, &segment_ids_);
}

Vec3 FlatTriangles::Barycentric(int f, const Vec2& p) const {
  const Vec2 st = inverse_[f] * (p - origin_[f]);
  return Vec3(1.0 - st.x() - st.y(), st.x(), st.y());
}

int FlatTriangles::Locate(const Vec2& p, Vec3* bary) const {
  constexpr double kIn = -1e-12;
  if (grid_.bounds().exteriorDistance(p) > 0.0) return -1;
  const int b = grid_.Bucket(grid_.CellOf(p));
  for (int k = triangle_start_[b]; k < triangle_start_[b + 1]; ++k) {
    const int f = triangle_ids_[k];
    const Vec3 l = Barycentric(f, p);
    if (l.minCoeff() >= kIn) {
      *bary = l;
      return f;
    }
  }
  return -1;
}

FlatTriangles::Nearest FlatTriangles::NearestOnBoundary(const Vec2& p) const {
  Nearest best;
  best.distance = std::numeric_limits<double>::infinity();
  auto consider = [&](int s) {
    const Vec2 q = NearestOnSegment(segments_[s][0], segments_[s][1], p);
    const double d = (q - p).norm();
    if (d < best.distance) {
      best.distance = d;
      best.point = q;
      best.triangle = segment_triangle_[s];
    }
  };
  // Rings of buckets round p's (its projection's, from outside the box: no
  // point of ring r is nearer than `outside` and (r - 1) cells together),
  // until no nearer segment can be left; past as many buckets as there are
  // segments, every segment instead: a query costs at most O(segments).
  const Eigen::Vector2i c = grid_.CellOf(p);
  const double step = grid_.cell().minCoeff();
  const double outside = grid_.bounds().exteriorDistance(p);
  const int most = std::max(grid_.columns(), grid_.rows());
  long long visited = 0;
  const long long budget = static_cast<long long>(segments_.size());
  for (int r = 0; r <= most; ++r) {
    const double ring = std::max(r - 1, 0) * step;
    if (r > 0 && std::sqrt(outside * outside + ring * ring) > best.distance) break;
    if (visited > budget) {
      for (size_t s = 0; s < segments_.size(); ++s) consider(static_cast<int>(s));
      break;
    }
    for (int y = c.y() - r; y <= c.y() + r; ++y) {
      if (y < 0 || y >= grid_.rows()) continue;
      const bool edge_row = y == c.y() - r || y == c.y() + r;
      for (int x = c.x() - r; x <= c.x() + r; x += edge_row ? 1 : 2 * std::max(r, 1)) {
        if (x < 0 || x >= grid_.columns()) continue;
        const int b = grid_.Bucket(Eigen::Vector2i(x, y));
        ++visited;
        for (int k = segment_start_[b]; k < segment_start_[b + 1]; ++k) consider(segment_ids_[k]);
      }
    }
  }
  return best;
}

}  // namespace surfdeform
