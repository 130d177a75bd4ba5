// Stress majorization of a periodic sheet; see
// flatten_solvers.hpp.
//
// The unknowns are the node positions Y of one period (node_columns x
// node_rows) and the periods T_a of the periodic directions (a = u, v). A
// pair's flat difference is Y_j + sum_a k_a T_a - Y_i, linear in (Y, T), so
// the Guttman transform solves the bordered system
//   [ L   C ] [Y]   [b_Y]
//   [ C'  S ] [T] = [b_T]
// with L the Laplacian of the neighbourhood graph wrapped round in the
// periodic directions (the spectral LaplacianFactor, periodic there),
// column a of C: c_a,i = sum over i's pairs of -+k_a, and S_ab = sum k_a k_b.
// With Q = L^+ C, fixed for the grid:
//   T = (S - Q' C)^-1 (b_T - Q' b_Y),   Y = L^+ b_Y - Q T,
// one spectral solve per coordinate per iteration, as for an open sheet.
#include <Eigen/Dense>
#include <array>
#include <cmath>

#include "engine/common/parallel.hpp"
#include "engine/flatten/flatten_solvers.hpp"

namespace surfdeform::internal {

std::vector<SeamEdge> PeriodicEdges(const SurfaceDistances& extended, const GridPeriods& periods,
                                    int max_ring) {
  const int nu = extended.nu;
  const int pu = periods.period_u, pv = periods.period_v;
  const int columns = periods.node_columns();
  std::vector<SeamEdge> out;
  out.reserve(extended.edges.size());
  auto node = [&](int index, int* su, int* sv) {
    const int column = index % nu, row = index / nu;
    *su = pu > 0 ? column / pu : 0;
    *sv = pv > 0 ? row / pv : 0;
    return (pu > 0 ? column % pu : column) + columns * (pv > 0 ? row % pv : row);
  };
  for (const GridEdge& e : extended.edges) {
    if (e.ring > max_ring) continue;
    if (pu > 0 && std::min(e.i % nu, e.j % nu) >= pu) continue;  // a copy a period on
    if (pv > 0 && std::min(e.i / nu, e.j / nu) >= pv) continue;
    SeamEdge s;
    int ui = 0, vi = 0, uj = 0, vj = 0;
    s.i = node(e.i, &ui, &vi);
    s.j = node(e.j, &uj, &vj);
    s.shift_u = uj - ui;
    s.shift_v = vj - vi;
    s.ring = e.ring;
    s.d = e.d;
    out.push_back(s);
  }
  return out;
}

namespace {

// B(X) X over edges [begin, end) into `rhs` ([Y_x, Y_y, T_u, T_v] like X,
// each T two coordinates); returns their stress.
double PeriodicGuttmanTerms(const std::vector<SeamEdge>& edges, int begin, int end,
                            const Eigen::VectorXd& x, int n, Eigen::VectorXd* rhs) {
  double* bx = rhs->data();
  double* by = bx + n;
  const double* px = x.data();
  const double* py = px + n;
  const double tux = x(2 * n), tuy = x(2 * n + 1), tvx = x(2 * n + 2), tvy = x(2 * n + 3);
  double bux = 0.0, buy = 0.0, bvx = 0.0, bvy = 0.0, stress = 0.0;
  for (int k = begin; k < end; ++k) {
    const SeamEdge& e = edges[k];
    const double dx = px[e.j] + e.shift_u * tux + e.shift_v * tvx - px[e.i];
    const double dy = py[e.j] + e.shift_u * tuy + e.shift_v * tvy - py[e.i];
    const double len = std::sqrt(dx * dx + dy * dy);
    stress += (e.d - len) * (e.d - len);
    if (!(len > 0.0)) continue;
    const double w = e.d / len;
    bx[e.j] += w * dx;
    by[e.j] += w * dy;
    bx[e.i] -= w * dx;
    by[e.i] -= w * dy;
    bux += e.shift_u * w * dx;
    buy += e.shift_u * w * dy;
    bvx += e.shift_v * w * dx;
    bvy += e.shift_v * w * dy;
  }
  (*rhs)(2 * n) += bux;
  (*rhs)(2 * n + 1) += buy;
  (*rhs)(2 * n + 2) += bvx;
  (*rhs)(2 * n + 3) += bvy;
  return stress;
}

}  // namespace

SolveStats SolvePeriodicMajorization(const LaplacianFactor& factor, const GridPeriods& periods,
                                     const std::vector<SeamEdge>& edges, double tolerance,
                                     int max_iterations, int threads, std::vector<Vec2>* nodes,
                                     Vec2* period_u, Vec2* period_v, Deadline deadline) {
  threads = ResolveThreads(threads);
  const int nu = factor.nu, nv = factor.nv, n = nu * nv;
  // The periodic directions (0: u, 1: v), and the border of the system.
  std::vector<int> active;
  if (periods.period_u > 0) active.push_back(0);
  if (periods.period_v > 0) active.push_back(1);
  const int m = static_cast<int>(active.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, 2);
  Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
  for (const SeamEdge& e : edges) {
    const std::array<int, 2> k = {e.shift_u, e.shift_v};
    for (int a = 0; a < 2; ++a) {
      c(e.j, a) += k[a];
      c(e.i, a) -= k[a];
      for (int b = 0; b < 2; ++b) s(a, b) += static_cast<double>(k[a]) * k[b];
    }
  }
  // Q = L^+ C, a column per periodic direction, solved as the two
  // coordinates of one right-hand side.
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(n, 2);
  {
    Eigen::MatrixXd both(nu, 2 * nv);
    both.leftCols(nv) = Eigen::Map<const Eigen::MatrixXd>(c.col(0).data(), nu, nv);
    both.rightCols(nv) = Eigen::Map<const Eigen::MatrixXd>(c.col(1).data(), nu, nv);
    factor.Solve(both, 1);
    q.col(0) = Eigen::Map<const Eigen::VectorXd>(both.data(), n);
    q.col(1) = Eigen::Map<const Eigen::VectorXd>(both.data() + n, n);
  }
  Eigen::MatrixXd schur(m, m);
  for (int a = 0; a < m; ++a) {
    for (int b = 0; b < m; ++b) {
      schur(a, b) = s(active[a], active[b]) - q.col(active[a]).dot(c.col(active[b]));
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> schur_ldlt(schur);

  Eigen::VectorXd x(2 * n + 4);
  for (int i = 0; i < n; ++i) {
    x(i) = (*nodes)[i].x();
    x(n + i) = (*nodes)[i].y();
  }
  x.segment<2>(2 * n) = *period_u;
  x.segment<2>(2 * n + 2) = *period_v;

  ChunkedGuttmanSum sum(edges.size(), 2 * n + 4, threads);
  MajorizationMap map;
  map.right_hand_side = [&](const Eigen::VectorXd& at, Eigen::VectorXd* rhs) {
    return sum.Sum(static_cast<int>(edges.size()), rhs,
                   [&](int begin, int end, Eigen::VectorXd* out) {
                     return PeriodicGuttmanTerms(edges, begin, end, at, n, out);
                   });
  };
  map.solve = [&](Eigen::VectorXd* b) {
    Eigen::MatrixXd t = Eigen::MatrixXd::Zero(2, 2);  // t(a, coordinate)
    for (int coordinate = 0; coordinate < 2; ++coordinate) {
      const auto by = b->segment(coordinate * n, n);
      Eigen::VectorXd rhs(m);
      for (int a = 0; a < m; ++a) {
        rhs(a) = (*b)(2 * n + 2 * active[a] + coordinate) - q.col(active[a]).dot(by);
      }
      const Eigen::VectorXd solved = schur_ldlt.solve(rhs);
      for (int a = 0; a < m; ++a) t(active[a], coordinate) = solved(a);
    }
    factor.Solve(Eigen::Map<Eigen::MatrixXd>(b->data(), nu, 2 * nv), threads);
    for (int coordinate = 0; coordinate < 2; ++coordinate) {
      b->segment(coordinate * n, n) -= q * t.col(coordinate);
    }
    for (int a = 0; a < 2; ++a) b->segment<2>(2 * n + 2 * a) = t.row(a).transpose();
  };
  double total = 0.0;
  for (const SeamEdge& e : edges) total += e.d * e.d;
  const SolveStats stats = IterateMajorization(map, total, tolerance, max_iterations, &x, deadline);
  for (int i = 0; i < n; ++i) (*nodes)[i] = Vec2(x(i), x(n + i));
  *period_u = x.segment<2>(2 * n);
  *period_v = x.segment<2>(2 * n + 2);
  return stats;
}

}  // namespace surfdeform::internal
