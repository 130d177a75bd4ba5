#include "engine/subdivision/cell_estimates.hpp"

#include <cmath>

#include "engine/common/parallel.hpp"
#include "engine/subdivision/grid_points.hpp"
#include "engine/subdivision/target_edges.hpp"

namespace surfdeform::subdivision {
namespace {

// Adds `index` to `list` once.
void AddOnce(std::vector<char>& flags, std::vector<int>& list, int index) {
  if (!flags[index]) {
    flags[index] = 1;
    list.push_back(index);
  }
}

// The cells within one cell of a vertex's, each once, by index: the cells
// that hold a vertex are marked first (one pass over the vertices), then
// grown by their neighbours (one pass over the cells).
std::vector<int> NeededCells(const CellGrid& grid, const IdVector<VertexId, int>& vertex_cell) {
  std::vector<char> holds(grid.cell_count(), 0);
  for (int c : vertex_cell) {
    if (c >= 0) holds[c] = 1;
  }
  std::vector<char> seen(grid.cell_count(), 0);
  for (int c = 0; c < static_cast<int>(holds.size()); ++c) {
    if (!holds[c]) continue;
    const GridIndex at = grid.CellAt(c);
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        if (grid.HasCell(at.i + di, at.j + dj)) seen[grid.Cell(at.i + di, at.j + dj)] = 1;
      }
  }
  std::vector<int> needed;
  for (size_t c = 0; c < seen.size(); ++c) {
    if (seen[c]) needed.push_back(static_cast<int>(c));
  }
  return needed;
}

// The kink across `side`: the second difference of F = S + h N across the
// side's middle, divided by the step, at the model's lowest and highest
// heights (|A + h B| is convex in h, so its largest value over the model's
// range is at one of them).
double SideKink(const Context& ctx, const CellGrid::Side& side, double h_lo, double h_hi,
                int* hint) {
  const GridIndex n = side.from;
  const Vec2& a = ctx.locator.Node(n.i, n.j);
  const Vec2& b = side.along_u ? ctx.locator.Node(n.i + 1, n.j) : ctx.locator.Node(n.i, n.j + 1);
  const double step = 1e-4 * (b - a).norm();
  const Vec2 across = Vec2(-(b - a).y(), (b - a).x()).normalized() * step;
  const Vec2 mid = 0.5 * (a + b);
  Vec3 sp[3], nn[3];
  const Vec2 at[3] = {mid, mid + across, mid - across};
  for (int w = 0; w < 3; ++w) ctx.map.SurfaceAndNormal(at[w], ctx.outside, hint, &sp[w], &nn[w]);
  const Vec3 d_surface = (sp[1] - sp[0]) - (sp[0] - sp[2]);
  const Vec3 d_normal = (nn[1] - nn[0]) - (nn[0] - nn[2]);
  return std::max((d_surface + h_lo * d_normal).norm(), (d_surface + h_hi * d_normal).norm()) /
         step;
}

// How fast the unit normal turns per unit length along u and along v at a
// surface point (Weingarten's equations over the arc length, which the
// sheet keeps); zero where the parametrization degenerates.
struct NormalRates {
  Vec3 along_u = Vec3::Zero();
  Vec3 along_v = Vec3::Zero();
};
NormalRates RatesAt(const SurfacePoint& s) {
  NormalRates r;
  const Vec3 n = UnitNormal(s);
  const double e = s.su.squaredNorm(), f = s.su.dot(s.sv), g = s.sv.squaredNorm();
  const double det = e * g - f * f;
  if (!(det > 0.0)) return r;
  const double l = s.suu.dot(n), m = s.suv.dot(n), nn = s.svv.dot(n);
  const Vec3 nu = ((f * m - g * l) * s.su + (f * l - e * m) * s.sv) / det;
  const Vec3 nv = ((f * nn - g * m) * s.su + (f * m - e * nn) * s.sv) / det;
  r.along_u = nu / std::sqrt(e);
  r.along_v = nv / std::sqrt(g);
  return r;
}

// The normal's second derivative along the sheet in a cell, at most, from
// the rates at its corners ([di][dj] slots in `rates`, p_ij their sheet
// positions): the differences of the rate along u across the cell's u sides
// (d2N/da2), of the rate along v across its v sides (d2N/db2), and of either
// across the other's sides (d2N/da db). For a unit direction (x, y),
// |x^2 N_aa + 2 x y N_ab + y^2 N_bb| <= max(|N_aa|, |N_bb|) + |N_ab|.
double Bend(const std::vector<NormalRates>& rates, const int (&slot)[2][2], const Vec2& p00,
            const Vec2& p10, const Vec2& p01, const Vec2& p11) {
  auto rate_of_change = [](const Vec3& from, const Vec3& to, const Vec2& a, const Vec2& b) {
    const double step = (b - a).norm();
    return step > 0.0 ? (to - from).norm() / step : 0.0;
  };
  const NormalRates &r00 = rates[slot[0][0]], &r10 = rates[slot[1][0]];
  const NormalRates &r01 = rates[slot[0][1]], &r11 = rates[slot[1][1]];
  const double aa = std::max(rate_of_change(r00.along_u, r10.along_u, p00, p10),
                             rate_of_change(r01.along_u, r11.along_u, p01, p11));
  const double bb = std::max(rate_of_change(r00.along_v, r01.along_v, p00, p01),
                             rate_of_change(r10.along_v, r11.along_v, p10, p11));
  const double ab = std::max({rate_of_change(r00.along_u, r01.along_u, p00, p01),
                              rate_of_change(r10.along_u, r11.along_u, p10, p11),
                              rate_of_change(r00.along_v, r10.along_v, p00, p10),
                              rate_of_change(r01.along_v, r11.along_v, p01, p11)});
  return std::max(aa, bb) + ab;
}

}  // namespace

CellEstimates::CellEstimates(const Context& ctx, const IdVector<VertexId, int>& vertex_cell)
    : grid_(ctx.grid) {
  cells_.assign(grid_.cell_count(), {});
  double h_lo = kInf, h_hi = -kInf;  // the model's range of heights
  for (const Vec3& p : ctx.placed) {
    h_lo = std::min(h_lo, p.z());
    h_hi = std::max(h_hi, p.z());
  }
  const std::vector<int> needed = NeededCells(grid_, vertex_cell);
  // The nodes (each with its slot in `nodes`) and the interior sides of those
  // cells, each once.
  std::vector<int> nodes, sides;
  std::vector<int> node_slot(grid_.node_count(), -1);
  std::vector<char> side_seen(grid_.side_count(), 0);
  const int cu = grid_.cells_u(), cv = grid_.cells_v();
  for (int c : needed) {
    const GridIndex at = grid_.CellAt(c);
    const int i = at.i, j = at.j;
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        int& slot = node_slot[grid_.Node(i + di, j + dj)];
        if (slot < 0) {
          slot = static_cast<int>(nodes.size());
          nodes.push_back(grid_.Node(i + di, j + dj));
        }
      }
    if (j > 0) AddOnce(side_seen, sides, grid_.SideAlongU(i, j));
    if (j + 1 < cv) AddOnce(side_seen, sides, grid_.SideAlongU(i, j + 1));
    if (i > 0) AddOnce(side_seen, sides, grid_.SideAlongV(i, j));
    if (i + 1 < cu) AddOnce(side_seen, sides, grid_.SideAlongV(i + 1, j));
  }
  // The largest principal curvature and the normal's rates of turning at
  // each node; the kink across each side.
  std::vector<double> node_curvature(nodes.size(), 0.0);
  std::vector<NormalRates> node_rates(nodes.size());
  side_kink_.assign(side_seen.size(), 0.0);
  const int node_count = static_cast<int>(nodes.size());
  const int count = node_count + static_cast<int>(sides.size());
  ParallelChunks(count, ctx.threads, [&](int, int begin, int end) {
    int hint = -1;
    for (int q = begin; q < end; ++q) {
      if (q < node_count) {
        const GridIndex n = grid_.NodeAt(nodes[q]);
        const SurfacePoint s = ctx.map.surface().Evaluate(static_cast<double>(n.i) / cu,
                                                          static_cast<double>(n.j) / cv, 2);
        node_curvature[q] = MaxAbsCurvature(s);
        node_rates[q] = RatesAt(s);
      } else {
        const int side = sides[q - node_count];
        side_kink_[side] = SideKink(ctx, grid_.SideAt(side), h_lo, h_hi, &hint);
      }
    }
  });
  for (int c : needed) {
    const GridIndex at = grid_.CellAt(c);
    const int i = at.i, j = at.j;
    int slot[2][2];  // [di][dj]
    double kappa = 0.0;
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        slot[di][dj] = node_slot[grid_.Node(i + di, j + dj)];
        kappa = std::max(kappa, node_curvature[slot[di][dj]]);
      }
    const Vec2 &p00 = ctx.locator.Node(i, j), &p10 = ctx.locator.Node(i + 1, j);
    const Vec2 &p01 = ctx.locator.Node(i, j + 1), &p11 = ctx.locator.Node(i + 1, j + 1);
    const double side = ctx.locator.CellMinSide(c);
    CellTerms& e = cells_[c];
    e.curvature = kappa;
    e.bend = Bend(node_rates, slot, p00, p10, p01, p11);
    e.min_side = side;
    e.twist = side > 0.0 ? (p00 - p10 + p11 - p01).norm() / (side * side) : kInf;
    if (ctx.target != nullptr) {
      // A mesh surface bends only across its edges, inside the cells.
      Eigen::AlignedBox2d box(p00);
      box.extend(p10).extend(p01).extend(p11);
      e.kink = ctx.target->MaxKinkIn(box, std::max(std::abs(h_lo), std::abs(h_hi)));
    }
  }
}

CellTerms CellEstimates::BlockTerms(int i0, int j0, int i1, int j1) const {
  const int cells[4] = {grid_.Cell(i0, j0), grid_.Cell(i1, j0), grid_.Cell(i0, j1),
                        grid_.Cell(i1, j1)};
  CellTerms t = cells_[cells[0]];
  for (int q = 1; q < 4; ++q) {
    const CellTerms& e = cells_[cells[q]];
    t.curvature = std::max(t.curvature, e.curvature);
    t.bend = std::max(t.bend, e.bend);
    t.kink = std::max(t.kink, e.kink);
    t.twist = std::max(t.twist, e.twist);
    t.min_side = std::min(t.min_side, e.min_side);
  }
  // Inside the block: the v-sides at i1 (when i1 > i0) and the u-sides at j1
  // (when j1 > j0).
  if (i1 > i0) {
    t.kink = std::max(
        {t.kink, side_kink_[grid_.SideAlongV(i1, j0)], side_kink_[grid_.SideAlongV(i1, j1)]});
  }
  if (j1 > j0) {
    t.kink = std::max(
        {t.kink, side_kink_[grid_.SideAlongU(i0, j1)], side_kink_[grid_.SideAlongU(i1, j1)]});
  }
  return t;
}

bool CellEstimates::BlockTermsOf(int a, int b, int c, CellTerms* terms) const {
  if (a < 0 || b < 0 || c < 0) return false;
  const GridIndex pa = grid_.CellAt(a), pb = grid_.CellAt(b), pc = grid_.CellAt(c);
  const int i0 = std::min({pa.i, pb.i, pc.i}), i1 = std::max({pa.i, pb.i, pc.i});
  const int j0 = std::min({pa.j, pb.j, pc.j}), j1 = std::max({pa.j, pb.j, pc.j});
  if (i1 - i0 > 1 || j1 - j0 > 1) return false;
  *terms = BlockTerms(i0, j0, i1, j1);
  return true;
}

}  // namespace surfdeform::subdivision

namespace surfdeform {

std::vector<FaceExtent> FaceExtents(const Mesh& mesh, const std::vector<Vec3>& placed) {
  std::vector<FaceExtent> out;
  out.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    out.push_back(subdivision::ExtentOfCorners(placed[t[0]], placed[t[1]], placed[t[2]]));
  }
  return out;
}

}  // namespace surfdeform
