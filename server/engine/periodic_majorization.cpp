// Stress majorization of a sheet periodic in u (issue #36); see
// flatten_solvers.hpp.
//
// The unknowns are the P x nv node positions Y (the columns of one period)
// and the period T. A pair's flat difference is Y_j + k T - Y_i, linear in
// (Y, T), so the Guttman transform solves the bordered system
//   [ L  c ] [Y]   [b_Y]
//   [ c' s ] [T] = [b_T]
// with L the Laplacian of the neighbourhood graph wrapped round in u (the
// spectral LaplacianFactor with periodic_u), c_i = sum over i's pairs of
// -+k, and s = sum k^2. With q = L^+ c, fixed for the grid:
//   T = (b_T - q' b_Y) / (s - q' c),   Y = L^+ b_Y - q T,
// one spectral solve per coordinate per iteration, as for an open sheet.
#include <cmath>

#include "engine/flatten_solvers.hpp"
#include "engine/parallel.hpp"

namespace surfdeform::internal {

std::vector<SeamEdge> PeriodicEdges(const SurfaceDistances& extended, int period, int max_ring) {
  const int nu = extended.nu;
  std::vector<SeamEdge> out;
  out.reserve(extended.edges.size());
  auto node = [&](int index, int* shift) {
    const int column = index % nu, row = index / nu;
    *shift = column / period;
    return column % period + period * row;
  };
  for (const GridEdge& e : extended.edges) {
    if (e.ring > max_ring || std::min(e.i % nu, e.j % nu) >= period) continue;
    SeamEdge s;
    int shift_i = 0, shift_j = 0;
    s.i = node(e.i, &shift_i);
    s.j = node(e.j, &shift_j);
    s.shift = shift_j - shift_i;
    s.ring = e.ring;
    s.d = e.d;
    out.push_back(s);
  }
  return out;
}

namespace {

// B(X) X over edges [begin, end) into `rhs` ([Y_x, Y_y, T_x, T_y] like X);
// returns their stress.
double PeriodicGuttmanTerms(const std::vector<SeamEdge>& edges, int begin, int end,
                            const Eigen::VectorXd& x, int n, Eigen::VectorXd* rhs) {
  double* bx = rhs->data();
  double* by = bx + n;
  const double* px = x.data();
  const double* py = px + n;
  const double tx = x(2 * n), ty = x(2 * n + 1);
  double btx = 0.0, bty = 0.0, stress = 0.0;
  for (int k = begin; k < end; ++k) {
    const SeamEdge& e = edges[k];
    const double dx = px[e.j] + e.shift * tx - px[e.i];
    const double dy = py[e.j] + e.shift * ty - py[e.i];
    const double len = std::sqrt(dx * dx + dy * dy);
    stress += (e.d - len) * (e.d - len);
    if (!(len > 0.0)) continue;
    const double w = e.d / len;
    bx[e.j] += w * dx;
    by[e.j] += w * dy;
    bx[e.i] -= w * dx;
    by[e.i] -= w * dy;
    btx += e.shift * w * dx;
    bty += e.shift * w * dy;
  }
  (*rhs)(2 * n) += btx;
  (*rhs)(2 * n + 1) += bty;
  return stress;
}

}  // namespace

SolveStats SolvePeriodicMajorization(const LaplacianFactor& factor,
                                     const std::vector<SeamEdge>& edges, double tolerance,
                                     int max_iterations, int threads, std::vector<Vec2>* nodes,
                                     Vec2* period, Deadline deadline) {
  threads = ResolveThreads(threads);
  const int p = factor.nu, nv = factor.nv, n = p * nv;
  // The border of the bordered system, and q = L^+ c.
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
  double s = 0.0;
  for (const SeamEdge& e : edges) {
    c(e.j) += e.shift;
    c(e.i) -= e.shift;
    s += static_cast<double>(e.shift) * e.shift;
  }
  Eigen::MatrixXd q2(p, 2 * nv);
  q2.leftCols(nv) = Eigen::Map<const Eigen::MatrixXd>(c.data(), p, nv);
  q2.rightCols(nv).setZero();
  factor.Solve(q2, 1);
  const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(q2.data(), n);
  const double schur = s - q.dot(c);

  Eigen::VectorXd x(2 * n + 2);
  for (int i = 0; i < n; ++i) {
    x(i) = (*nodes)[i].x();
    x(n + i) = (*nodes)[i].y();
  }
  x(2 * n) = period->x();
  x(2 * n + 1) = period->y();

  ChunkedGuttmanSum sum(edges.size(), 2 * n + 2, threads);
  MajorizationMap map;
  map.right_hand_side = [&](const Eigen::VectorXd& at, Eigen::VectorXd* rhs) {
    return sum.Sum(static_cast<int>(edges.size()), rhs,
                   [&](int begin, int end, Eigen::VectorXd* out) {
                     return PeriodicGuttmanTerms(edges, begin, end, at, n, out);
                   });
  };
  map.solve = [&](Eigen::VectorXd* b) {
    const double tx = ((*b)(2 * n) - q.dot(b->head(n))) / schur;
    const double ty = ((*b)(2 * n + 1) - q.dot(b->segment(n, n))) / schur;
    factor.Solve(Eigen::Map<Eigen::MatrixXd>(b->data(), p, 2 * nv), threads);
    b->head(n) -= tx * q;
    b->segment(n, n) -= ty * q;
    (*b)(2 * n) = tx;
    (*b)(2 * n + 1) = ty;
  };
  double total = 0.0;
  for (const SeamEdge& e : edges) total += e.d * e.d;
  const SolveStats stats = IterateMajorization(map, total, tolerance, max_iterations, &x, deadline);
  for (int i = 0; i < n; ++i) (*nodes)[i] = Vec2(x(i), x(n + i));
  *period = Vec2(x(2 * n), x(2 * n + 1));
  return stats;
}

}  // namespace surfdeform::internal
