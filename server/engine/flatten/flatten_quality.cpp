// Canonical frame and quality measures of a flat sheet; see flatten.hpp.
#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/flatten/flatten_solvers.hpp"

namespace surfdeform::internal {
namespace {

// Signed area of the quad a, b, c, d (shoelace).
double QuadArea(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  return 0.5 * Cross2(c - a, d - b);
}

}  // namespace

void Canonicalize(int nu, int nv, std::vector<Vec2>* x, Eigen::Matrix2d* linear_out,
                  Vec2* offset_out) {
  std::vector<Vec2>& p = *x;
  const Vec2 origin = p[0];
  for (Vec2& q : p) q -= origin;
  const Vec2 axis = p[1];  // sample (1, 0)
  const double len = axis.norm();
  Eigen::Matrix2d linear = Eigen::Matrix2d::Identity();
  if (len > 0.0) {
    const double c = axis.x() / len;
    const double s = axis.y() / len;
    linear << c, s, -s, c;
    for (Vec2& q : p) q = linear * q;
  }
  double signed_area = 0.0;
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i + 1 < nu; ++i) {
      const int a = i + nu * j;
      signed_area += QuadArea(p[a], p[a + 1], p[a + 1 + nu], p[a + nu]);
    }
  }
  if (signed_area < 0.0) {
    for (Vec2& q : p) q.y() = -q.y();
    linear.row(1) *= -1.0;
  }
  if (linear_out != nullptr) *linear_out = linear;
  if (offset_out != nullptr) *offset_out = -(linear * origin);
}

void MeasureQuality(const SurfaceDistances& dist, const std::vector<Vec2>& x, FlattenQuality* q,
                    int cell_columns, int cell_rows) {
  const int nu = dist.nu;
  const int nv = dist.nv;
  const int columns = cell_columns < 0 ? nu - 1 : std::min(cell_columns, nu - 1);
  const int rows = cell_rows < 0 ? nv - 1 : std::min(cell_rows, nv - 1);
  double c = 0.0;
  double total = 0.0;
  double max_edge = 0.0;
  for (const GridEdge& e : dist.edges) {
    if (e.ring > 3) continue;
    const double len = (x[e.i] - x[e.j]).norm();
    c += (e.d - len) * (e.d - len);
    total += e.d * e.d;
    if (e.ring == 1 && (e.di == 0 || e.dj == 0)) {
      max_edge = std::max(max_edge, std::abs(len - e.d) / e.d);
    }
  }
  q->stress = total > 0.0 ? std::sqrt(c / total) : 0.0;
  q->max_edge_error = max_edge;
  q->area_ratio_min = std::numeric_limits<double>::infinity();
  q->area_ratio_max = 0.0;
  q->folded_cells = 0;
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < columns; ++i) {
      const int ia = i + nu * j;
      const Vec2& a = x[ia];
      const Vec2& b = x[ia + 1];
      const Vec2& cc = x[ia + 1 + nu];
      const Vec2& d = x[ia + nu];
      // Inverted or non-convex: some corner turns the wrong way.
      const bool folded = Cross2(a - d, b - a) <= 0.0 || Cross2(b - a, cc - b) <= 0.0 ||
                          Cross2(cc - b, d - cc) <= 0.0 || Cross2(d - cc, a - d) <= 0.0;
      q->folded_cells += folded ? 1 : 0;
      const double ratio = QuadArea(a, b, cc, d) / dist.cell_areas[i + (nu - 1) * j];
      q->area_ratio_min = std::min(q->area_ratio_min, ratio);
      q->area_ratio_max = std::max(q->area_ratio_max, ratio);
    }
  }
}

}  // namespace surfdeform::internal

namespace surfdeform {

FlattenQuality MeasureLayout(const SurfaceDistances& distances, int nu, int nv,
                             std::vector<Vec2>* flat) {
  internal::Canonicalize(nu, nv, flat);
  FlattenQuality q;
  internal::MeasureQuality(distances, *flat, &q);
  return q;
}

}  // namespace surfdeform
