#include "engine/subdivision/grid_points.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace surfdeform {
namespace {

// A side of a cell: a piece of one grid line between two adjacent nodes.
struct Side {
  int line;  // u-lines 0 .. nu-1, v-lines nu .. nu+nv-1
  int seg;   // the piece from node `seg` to `seg + 1` along the line
  bool operator<(const Side& o) const { return line != o.line ? line < o.line : seg < o.seg; }
  bool operator==(const Side& o) const { return line == o.line && seg == o.seg; }
};

}  // namespace

void GridCrossings(const FlatLocator& locator, const Vec2& a, const Vec2& b,
                   std::vector<GridCrossing>* out, std::vector<int>* scratch,
                   double* min_cell_side) {
  out->clear();
  *min_cell_side = std::numeric_limits<double>::infinity();
  const Vec2 d = b - a;
  const double len = d.norm();
  if (!(len > 0.0)) return;
  const int nu = locator.nu();
  locator.CellsAlongSegment(a, b, scratch);
  std::vector<Side> sides;
  sides.reserve(4 * scratch->size());
  for (int cell : *scratch) {
    const int i = cell % (nu - 1), j = cell / (nu - 1);
    *min_cell_side = std::min(*min_cell_side, locator.CellMinSide(cell));
    sides.push_back({i, j});
    sides.push_back({i + 1, j});
    sides.push_back({nu + j, i});
    sides.push_back({nu + j + 1, i});
  }
  std::sort(sides.begin(), sides.end());
  sides.erase(std::unique(sides.begin(), sides.end()), sides.end());
  constexpr double kEnd = 1e-7;    // crossings this close to an end belong to it
  constexpr double kSlack = 1e-9;  // along a side: a node belongs to both pieces
  for (const Side& side : sides) {
    const bool u_line = side.line < nu;
    const int index = u_line ? side.line : side.line - nu;
    const Vec2& p = u_line ? locator.Node(index, side.seg) : locator.Node(side.seg, index);
    const Vec2& q = u_line ? locator.Node(index, side.seg + 1) : locator.Node(side.seg + 1, index);
    const Vec2 e = q - p;
    const double den = Cross2(d, e);
    if (std::abs(den) <= 1e-12 * len * e.norm()) continue;  // parallel
    const Vec2 w = p - a;
    const double t = Cross2(w, e) / den;
    const double s = Cross2(w, d) / den;
    if (!(t > kEnd && t < 1.0 - kEnd && s >= -kSlack && s <= 1.0 + kSlack)) continue;
    GridCrossing c;
    c.t = t;
    const double along = side.seg + std::clamp(s, 0.0, 1.0);
    if (u_line) {
      c.u_line = index;
      c.u_along = along;
    } else {
      c.v_line = index;
      c.v_along = along;
    }
    out->push_back(c);
  }
  std::sort(out->begin(), out->end(), [](const GridCrossing& x, const GridCrossing& y) {
    if (x.t != y.t) return x.t < y.t;
    return x.u_line != y.u_line ? x.u_line < y.u_line : x.v_line < y.v_line;
  });
  // Merge coincident crossings: the same line found on two pieces (at a
  // node), or a u-line and a v-line through the same node.
  size_t kept = 0;
  for (size_t k = 0; k < out->size(); ++k) {
    GridCrossing& c = (*out)[k];
    if (kept > 0 && (c.t - (*out)[kept - 1].t) <= kEnd) {
      GridCrossing& prev = (*out)[kept - 1];
      if (c.u_line >= 0 && prev.u_line < 0) {
        prev.u_line = c.u_line;
        prev.u_along = c.u_along;
      }
      if (c.v_line >= 0 && prev.v_line < 0) {
        prev.v_line = c.v_line;
        prev.v_along = c.v_along;
      }
      continue;
    }
    (*out)[kept++] = c;
  }
  out->resize(kept);
}

void GridNodesInside(const FlatLocator& locator, const Vec2& a, const Vec2& b, const Vec2& c,
                     std::vector<GridNodeInside>* out, std::vector<int>* scratch) {
  out->clear();
  const double area2 = Cross2(b - a, c - a);
  const double size = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  if (!(std::abs(area2) > 1e-12 * size * size)) return;
  Eigen::AlignedBox2d box;
  box.extend(a).extend(b).extend(c);
  locator.CellsInBox(box, scratch);
  const int nu = locator.nu();
  // Distances to the sides, relative to the size: 2 area * l_k / |side k|.
  const double min_l0 = 1e-7 * size * (c - b).norm() / std::abs(area2);
  const double min_l1 = 1e-7 * size * (a - c).norm() / std::abs(area2);
  const double min_l2 = 1e-7 * size * (b - a).norm() / std::abs(area2);
  std::vector<long long> nodes;
  nodes.reserve(4 * scratch->size());
  for (int cell : *scratch) {
    const int i = cell % (nu - 1), j = cell / (nu - 1);
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) nodes.push_back(static_cast<long long>(j + dj) * nu + i + di);
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  for (long long id : nodes) {
    const int i = static_cast<int>(id % nu), j = static_cast<int>(id / nu);
    const Vec2& x = locator.Node(i, j);
    if (!box.contains(x)) continue;
    const double l1 = Cross2(x - a, c - a) / area2;  // area(a, x, c) / area(a, b, c)
    const double l2 = Cross2(b - a, x - a) / area2;  // area(a, b, x) / area(a, b, c)
    const double l0 = 1.0 - l1 - l2;
    if (l0 > min_l0 && l1 > min_l1 && l2 > min_l2) out->push_back({i, j, l1, l2});
  }
}

double NormalCurvature(const SurfacePoint& s, const Vec2& duv) {
  const Vec3 n = UnitNormal(s);
  const double du = duv.x(), dv = duv.y();
  const double first =
      s.su.squaredNorm() * du * du + 2.0 * s.su.dot(s.sv) * du * dv + s.sv.squaredNorm() * dv * dv;
  if (!(first > 0.0)) return 0.0;
  const double second =
      s.suu.dot(n) * du * du + 2.0 * s.suv.dot(n) * du * dv + s.svv.dot(n) * dv * dv;
  return second / first;
}

double MaxAbsCurvature(const SurfacePoint& s) {
  const Vec3 n = UnitNormal(s);
  const double e = s.su.squaredNorm(), f = s.su.dot(s.sv), g = s.sv.squaredNorm();
  const double l = s.suu.dot(n), m = s.suv.dot(n), nn = s.svv.dot(n);
  const double det = e * g - f * f;
  if (!(det > 0.0)) return 0.0;
  const double mean = (e * nn - 2.0 * f * m + g * l) / (2.0 * det);
  const double gauss = (l * nn - m * m) / det;
  return std::abs(mean) + std::sqrt(std::max(0.0, mean * mean - gauss));
}

}  // namespace surfdeform
