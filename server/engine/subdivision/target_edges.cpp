#include "engine/subdivision/target_edges.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/common/clamped_floor.hpp"

namespace surfdeform::subdivision {
namespace {

// The derivative along sheet direction d of the per-vertex `values`
// interpolated linearly over triangle t (`sheet`: the vertices on the
// sheet): the positions give the map's, the normals the normal field's.
Vec3 DerivativeAlong(const FlatMesh& m, const std::vector<Vec2>& sheet,
                     const std::vector<Vec3>& values, int t, const Vec2& d) {
  const auto& tri = m.mesh.triangles[t];
  const Vec2 e1 = sheet[tri[1]] - sheet[tri[0]], e2 = sheet[tri[2]] - sheet[tri[0]];
  const Vec3 p1 = values[tri[1]] - values[tri[0]];
  const Vec3 p2 = values[tri[2]] - values[tri[0]];
  const double det = Cross2(e1, e2);
  if (!(std::abs(det) > 0.0)) return Vec3::Zero();
  // d = x e1 + y e2
  const double x = Cross2(d, e2) / det, y = Cross2(e1, d) / det;
  return x * p1 + y * p2;
}

}  // namespace

TargetEdges::TargetEdges(const FlatMesh& mesh, const Eigen::Matrix2d& linear, const Vec2& offset) {
  const DiskMesh& m = mesh.mesh;
  flat_.reserve(mesh.flat.size());
  for (const Vec2& p : mesh.flat) flat_.push_back(linear * p + offset);
  const int nv = static_cast<int>(flat_.size());
  // Each edge once, from the triangle that holds it first (its neighbour,
  // if any, across it).
  for (int t = 0; t < static_cast<int>(m.triangles.size()); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int u = m.neighbours[t][k];
      if (u >= 0 && u < t) continue;  // listed from u
      const int a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
      Edge e;
      e.v = {std::min(a, b), std::max(a, b)};
      const Vec2 along = flat_[b] - flat_[a];
      e.length = along.norm();
      if (u >= 0 && e.length > 0.0) {
        const Vec2 across = Vec2(-along.y(), along.x()) / e.length;
        auto jump = [&](const std::vector<Vec3>& values) {
          return (DerivativeAlong(mesh, flat_, values, t, across) -
                  DerivativeAlong(mesh, flat_, values, u, across))
              .norm();
        };
        e.kink = jump(m.positions);
        if (mesh.normals.size() == m.positions.size()) e.normal_kink = jump(mesh.normals);
      }
      edges_.push_back(e);
    }
  }
  incident_start_.assign(nv + 1, 0);
  for (const Edge& e : edges_) {
    ++incident_start_[e.v[0] + 1];
    ++incident_start_[e.v[1] + 1];
  }
  for (int v = 0; v < nv; ++v) incident_start_[v + 1] += incident_start_[v];
  incident_.resize(incident_start_.back());
  std::vector<int> fill(incident_start_.begin(), incident_start_.end() - 1);
  for (int k = 0; k < static_cast<int>(edges_.size()); ++k) {
    incident_[fill[edges_[k].v[0]]++] = k;
    incident_[fill[edges_[k].v[1]]++] = k;
  }

  Eigen::AlignedBox2d bounds;
  for (const Vec2& p : flat_) bounds.extend(p);
  grid_ = UniformBuckets(bounds, static_cast<double>(edges_.size()));  // about one edge a bucket
  grid_.Fill(
      static_cast<int>(edges_.size()),
      [&](int k) {
        Eigen::AlignedBox2d b(flat_[edges_[k].v[0]]);
        b.extend(flat_[edges_[k].v[1]]);
        return b;
      },
      &edge_start_, &edge_ids_);
  grid_.Fill(
      nv, [&](int v) { return Eigen::AlignedBox2d(flat_[v], flat_[v]); }, &vertex_start_,
      &vertex_ids_);
}

template <typename Visit>
void TargetEdges::ForBucketsAlong(const Vec2& a, const Vec2& b, Visit&& visit) const {
  // The segment clipped to the buckets' box (Liang-Barsky), in bucket units.
  const Eigen::AlignedBox2d& bounds = grid_.bounds();
  const Vec2& cell = grid_.cell();
  const int columns = grid_.columns(), rows = grid_.rows();
  const Vec2 lo = bounds.min(), d = b - a;
  double t0 = 0.0, t1 = 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    const double p0 = a[axis], span = d[axis];
    const double min = lo[axis], max = bounds.max()[axis];
    if (span == 0.0) {
      if (p0 < min || p0 > max) return;
      continue;
    }
    double ta = (min - p0) / span, tb = (max - p0) / span;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return;
  }
  const Vec2 from = (a + t0 * d - lo).cwiseQuotient(cell);
  const Vec2 to = (a + t1 * d - lo).cwiseQuotient(cell);
  auto clamp_x = [&](double v) { return ClampedFloor(v, 0, columns - 1); };
  auto clamp_y = [&](double v) { return ClampedFloor(v, 0, rows - 1); };
  int x = clamp_x(from.x()), y = clamp_y(from.y());
  const int x_end = clamp_x(to.x()), y_end = clamp_y(to.y());
  const Vec2 step_d = to - from;
  const int sx = step_d.x() > 0 ? 1 : -1, sy = step_d.y() > 0 ? 1 : -1;
  // The segment's parameter (0 at `from`, 1 at `to`) at the next bucket
  // boundary in x and in y, and between boundaries.
  const double dx = std::abs(step_d.x()), dy = std::abs(step_d.y());
  const double inf = std::numeric_limits<double>::infinity();
  double next_x = dx > 0 ? ((sx > 0 ? x + 1 - from.x() : from.x() - x) / dx) : inf;
  double next_y = dy > 0 ? ((sy > 0 ? y + 1 - from.y() : from.y() - y) / dy) : inf;
  const double delta_x = dx > 0 ? 1.0 / dx : inf, delta_y = dy > 0 ? 1.0 / dy : inf;
  const int steps = std::abs(x_end - x) + std::abs(y_end - y);
  visit(x + columns * y);
  for (int k = 0; k < steps && (x != x_end || y != y_end); ++k) {
    if (std::abs(next_x - next_y) <= 1e-12) {
      // Through a corner: the buckets on both sides of it too.
      if (x + sx >= 0 && x + sx < columns) visit(x + sx + columns * y);
      if (y + sy >= 0 && y + sy < rows) visit(x + columns * (y + sy));
    }
    if (next_x < next_y || (next_x == next_y && x != x_end)) {
      if (x == x_end) break;
      x += sx;
      next_x += delta_x;
    } else {
      if (y == y_end) break;
      y += sy;
      next_y += delta_y;
    }
    visit(x + columns * y);
  }
}

void TargetEdges::Crossings(const Vec2& a, const Vec2& b, std::vector<GridCrossing>* out,
                            double* min_length, std::vector<int>* scratch) const {
  out->clear();
  *min_length = std::numeric_limits<double>::infinity();
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  if (!(len2 > 0.0)) return;
  // The edges in the buckets along the segment, each once.
  scratch->clear();
  ForBucketsAlong(a, b, [&](int bucket) {
    scratch->insert(scratch->end(), edge_ids_.begin() + edge_start_[bucket],
                    edge_ids_.begin() + edge_start_[bucket + 1]);
  });
  std::sort(scratch->begin(), scratch->end());
  scratch->erase(std::unique(scratch->begin(), scratch->end()), scratch->end());
  const double end_gap = 1e-7;
  for (int k : *scratch) {
    const Vec2& p = flat_[edges_[k].v[0]];
    const Vec2 e = flat_[edges_[k].v[1]] - p;
    const double den = Cross2(d, e);
    // Parallel (or along it): no crossing in the interior.
    if (!(std::abs(den) > 1e-12 * std::sqrt(len2) * e.norm())) continue;
    const Vec2 ap = p - a;
    const double t = Cross2(ap, e) / den;  // along a-b
    const double s = Cross2(ap, d) / den;  // along the edge
    if (!(t > end_gap && t < 1.0 - end_gap && s >= 0.0 && s <= 1.0)) continue;
    GridCrossing c;
    c.t = t;
    c.u_line = k;
    c.u_along = s;
    out->push_back(c);
    *min_length = std::min(*min_length, edges_[k].length);
  }
  // Where a-b passes through a target vertex it crosses several edges at one
  // point: one crossing stands for them, the edge there that kinks most.
  std::sort(out->begin(), out->end(),
            [](const GridCrossing& x, const GridCrossing& y) { return x.t < y.t; });
  size_t kept = 0;
  for (size_t k = 0; k < out->size(); ++k) {
    const GridCrossing& c = (*out)[k];
    if (kept > 0 && c.t - (*out)[kept - 1].t <= 1e-9) {
      if (edges_[c.u_line].kink > edges_[(*out)[kept - 1].u_line].kink) (*out)[kept - 1] = c;
      continue;
    }
    (*out)[kept++] = c;
  }
  out->resize(kept);
}

void TargetEdges::VerticesInside(const Vec2& a, const Vec2& b, const Vec2& c,
                                 std::vector<GridNodeInside>* out) const {
  out->clear();
  const double det = Cross2(b - a, c - a);
  const double size = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  if (!(std::abs(det) > 1e-12 * size * size)) return;
  Eigen::AlignedBox2d box(a);
  box.extend(b);
  box.extend(c);
  const double margin = 1e-7;
  // A bucket wholly outside one of the triangle's sides is skipped: a long
  // thin face's box spans many buckets that it does not touch.
  const double orientation = det > 0.0 ? 1.0 : -1.0;
  const Vec2 corners[3] = {a, b, c};
  auto outside = [&](int bucket) {
    const Vec2& cell = grid_.cell();
    const int columns = grid_.columns();
    const Vec2 lo =
        grid_.bounds().min() + Vec2(bucket % columns, bucket / columns).cwiseProduct(cell);
    const Vec2 box_corners[4] = {lo, lo + Vec2(cell.x(), 0), lo + Vec2(0, cell.y()), lo + cell};
    for (int k = 0; k < 3; ++k) {
      const Vec2 &p = corners[k], e = corners[(k + 1) % 3] - p;
      bool all_out = true;
      for (const Vec2& q : box_corners) all_out = all_out && orientation * Cross2(e, q - p) < 0.0;
      if (all_out) return true;
    }
    return false;
  };
  grid_.ForBox(box, [&](int bucket) {
    if (outside(bucket)) return;
    for (int q = vertex_start_[bucket]; q < vertex_start_[bucket + 1]; ++q) {
      const int v = vertex_ids_[q];
      const Vec2 p = flat_[v] - a;
      const double l1 = Cross2(p, c - a) / det, l2 = Cross2(b - a, p) / det;
      const double l0 = 1.0 - l1 - l2;
      if (l0 > margin && l1 > margin && l2 > margin) out->push_back({v, -1, l1, l2});
    }
  });
  std::sort(out->begin(), out->end(),
            [](const GridNodeInside& x, const GridNodeInside& y) { return x.i < y.i; });
}

double TargetEdges::MaxKinkIn(const Eigen::AlignedBox2d& box, double h) const {
  double kink = 0.0;
  grid_.ForBox(box, [&](int bucket) {
    for (int q = edge_start_[bucket]; q < edge_start_[bucket + 1]; ++q) {
      kink = std::max(kink, edges_[edge_ids_[q]].KinkAt(h));
    }
  });
  return kink;
}

}  // namespace surfdeform::subdivision
