// Stress majorization (SMACOF) with unit weights; see flatten.hpp.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "engine/common/parallel.hpp"
#include "engine/flatten/flatten_solvers.hpp"

namespace surfdeform::internal {

namespace {

// Eigen-decomposition of S = D^-1/2 B D^-1/2 for the band matrix B of ones
// within distance r (see LaplacianFactor); with `periodic`, within circular
// distance r (n >= 2 r + 1: the band does not meet itself).
void BandSpectrum(int n, int r, bool periodic, Eigen::MatrixXd* w, Eigen::VectorXd* mu,
                  Eigen::VectorXd* rs) {
  auto within = [&](int i, int k) {
    const int d = std::abs(i - k);
    return d <= r || (periodic && n - d <= r);
  };
  Eigen::MatrixXd s(n, n);
  rs->resize(n);
  for (int i = 0; i < n; ++i) {
    const int count = periodic ? 2 * r + 1 : std::min(n - 1, i + r) - std::max(0, i - r) + 1;
    (*rs)(i) = 1.0 / std::sqrt(static_cast<double>(count));
  }
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) s(i, k) = within(i, k) ? (*rs)(i) * (*rs)(k) : 0.0;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s);
  *w = eig.eigenvectors();
  *mu = eig.eigenvalues();
}

}  // namespace

std::unique_ptr<LaplacianFactor> FactorLaplacian(int nu, int nv, int range, bool periodic_u,
                                                 bool periodic_v) {
  auto f = std::make_unique<LaplacianFactor>();
  f->nu = nu;
  f->nv = nv;
  f->range = range;
  f->periodic_u = periodic_u;
  f->periodic_v = periodic_v;
  Eigen::VectorXd mu_u, mu_v;
  BandSpectrum(nu, range, periodic_u, &f->wu, &mu_u, &f->ru);
  BandSpectrum(nv, range, periodic_v, &f->wv, &mu_v, &f->rv);
  f->inverse_spectrum.resize(nu, nv);
  for (int b = 0; b < nv; ++b) {
    for (int a = 0; a < nu; ++a) {
      const double lambda = 1.0 - mu_u(a) * mu_v(b);
      // The graph is connected: only the constant mode (mu_u = mu_v = 1) has
      // lambda = 0. Right-hand sides are orthogonal to it.
      f->inverse_spectrum(a, b) = lambda > 1e-10 ? 1.0 / lambda : 0.0;
    }
  }
  return f;
}

void LaplacianFactor::SolveBlock(Eigen::Ref<Eigen::MatrixXd> y, Eigen::MatrixXd* scratch) const {
  Eigen::MatrixXd& z = *scratch;
  y = ru.asDiagonal() * y * rv.asDiagonal();
  z.noalias() = wu.transpose() * y;
  y.noalias() = z * wv;
  y.array() *= inverse_spectrum.array();
  z.noalias() = y * wv.transpose();
  y.noalias() = wu * z;
  y = ru.asDiagonal() * y * rv.asDiagonal();
}

void LaplacianFactor::Solve(Eigen::Ref<Eigen::MatrixXd> b, int threads) const {
  // Below ~64 x 64 samples a thread costs more than it saves.
  const int workers = nu * nv >= 4096 ? std::min(threads, 2) : 1;
  ParallelChunks(2, workers, [&](int, int c0, int c1) {
    Eigen::MatrixXd scratch(nu, nv);
    for (int c = c0; c < c1; ++c) SolveBlock(b.middleCols(c * nv, nv), &scratch);
  });
}

double GuttmanTerms(const std::vector<GridEdge>& edges, size_t begin, size_t end,
                    const Eigen::VectorXd& x, int n, Eigen::VectorXd* rhs) {
  double* bx = rhs->data();
  double* by = bx + n;
  const double* px = x.data();
  const double* py = px + n;
  double stress = 0.0;
  for (size_t k = begin; k < end; ++k) {
    const GridEdge& e = edges[k];
    const double dx = px[e.i] - px[e.j];
    const double dy = py[e.i] - py[e.j];
    const double len = std::sqrt(dx * dx + dy * dy);
    if (e.d < 0.0) {  // a free pair: its current length, no stress
      bx[e.i] += dx;
      by[e.i] += dy;
      bx[e.j] -= dx;
      by[e.j] -= dy;
      continue;
    }
    stress += (e.d - len) * (e.d - len);
    if (!(len > 0.0)) continue;
    const double w = e.d / len;
    bx[e.i] += w * dx;
    by[e.i] += w * dy;
    bx[e.j] -= w * dx;
    by[e.j] -= w * dy;
  }
  return stress;
}

ChunkedGuttmanSum::ChunkedGuttmanSum(size_t edges, int size, int threads)
    : chunks_(edges >= 50000 ? ResolveThreads(threads) : 1) {
  partial_.assign(chunks_ - 1, Eigen::VectorXd(size));
  stress_.assign(chunks_, 0.0);
}

double ChunkedGuttmanSum::Sum(int count, Eigen::VectorXd* rhs, const Terms& terms) {
  ParallelChunks(count, chunks_, [&](int chunk, int begin, int end) {
    Eigen::VectorXd* out = chunk == 0 ? rhs : &partial_[chunk - 1];
    out->setZero();
    stress_[chunk] = terms(begin, end, out);
  });
  double stress = stress_[0];
  for (int c = 1; c < chunks_; ++c) {
    *rhs += partial_[c - 1];
    stress += stress_[c];
  }
  return stress;
}

SolveStats IterateMajorization(const MajorizationMap& map, double total, double tolerance,
                               int max_iterations, Eigen::VectorXd* x_io, Deadline deadline,
                               double zero) {
  Eigen::VectorXd& x = *x_io;
  Eigen::VectorXd g(x.size());  // B(X) X, then G(X) after the solve

  // Anderson acceleration (type II, window kWindow) of the fixed-point map
  // X -> G(X): the next X combines the last G values so as to cancel the last
  // residuals G(X) - X in the least-squares sense. Safeguarded: a combination
  // that raises the stress is dropped for the plain G of the previous X, whose
  // stress majorization guarantees not to be higher.
  constexpr int kWindow = 5;
  std::vector<Eigen::VectorXd> hist_f, hist_g;  // residuals and G values, oldest first
  Eigen::VectorXd plain_g;                      // G of the previous X
  bool accelerated = false;

  SolveStats stats;
  double previous = 0.0;
  for (int it = 0;; ++it) {
    double stress = map.right_hand_side(x, &g);
    if (accelerated && !(stress <= previous)) {
      x = plain_g;  // reject the accelerated step
      hist_f.clear();
      hist_g.clear();
      stress = map.right_hand_side(x, &g);
    }
    if (it > 0 && StressSettled(previous, stress, tolerance, total, zero)) {
      stats.converged = true;
      break;
    }
    if (it == max_iterations) break;
    if (deadline.Passed()) {
      stats.out_of_time = true;
      break;
    }
    previous = stress;
    map.solve(&g);
    stats.iterations = it + 1;

    hist_f.push_back(g - x);
    hist_g.push_back(g);
    if (static_cast<int>(hist_f.size()) > kWindow + 1) {
      hist_f.erase(hist_f.begin());
      hist_g.erase(hist_g.begin());
    }
    plain_g = g;
    const int m = static_cast<int>(hist_f.size()) - 1;
    accelerated = m > 0;
    if (!accelerated) {
      x = g;
      continue;
    }
    const Eigen::Index size = x.size();
    Eigen::MatrixXd df(size, m);
    for (int k = 0; k < m; ++k) df.col(k) = hist_f[k + 1] - hist_f[k];
    Eigen::MatrixXd normal = df.transpose() * df;
    normal.diagonal().array() += 1e-12 * normal.diagonal().maxCoeff() + 1e-300;
    const Eigen::VectorXd gamma = normal.ldlt().solve(df.transpose() * hist_f.back());
    x = g;
    for (int k = 0; k < m; ++k) x -= gamma(k) * (hist_g[k + 1] - hist_g[k]);
    if (!x.allFinite()) {
      x = g;
      accelerated = false;
      hist_f.clear();
      hist_g.clear();
    }
  }
  return stats;
}

SolveStats SolveMajorization(const LaplacianFactor& factor, const std::vector<GridEdge>& edges,
                             double tolerance, int max_iterations, int threads,
                             std::vector<Vec2>* positions, Deadline deadline) {
  threads = ResolveThreads(threads);
  const int nu = factor.nu, nv = factor.nv;
  // The x block then the y block is the layout of the nu x 2nv right-hand side.
  return MajorizeLayout(
      [&](Eigen::VectorXd* rhs) {
        factor.Solve(Eigen::Map<Eigen::MatrixXd>(rhs->data(), nu, 2 * nv), threads);
      },
      edges, tolerance, max_iterations, threads, positions, deadline);
}

SolveStats MajorizeLayout(const std::function<void(Eigen::VectorXd*)>& solve,
                          const std::vector<GridEdge>& edges, double tolerance, int max_iterations,
                          int threads, std::vector<Vec2>* positions, Deadline deadline,
                          double zero) {
  const int n = static_cast<int>(positions->size());
  // X as one vector: all x coordinates, then all y coordinates.
  Eigen::VectorXd x(2 * n);
  for (int i = 0; i < n; ++i) {
    x(i) = (*positions)[i].x();
    x(n + i) = (*positions)[i].y();
  }
  ChunkedGuttmanSum sum(edges.size(), 2 * n, threads);
  MajorizationMap map;
  map.right_hand_side = [&](const Eigen::VectorXd& at, Eigen::VectorXd* rhs) {
    return sum.Sum(static_cast<int>(edges.size()), rhs,
                   [&](int begin, int end, Eigen::VectorXd* out) {
                     return GuttmanTerms(edges, begin, end, at, n, out);
                   });
  };
  map.solve = solve;
  const SolveStats stats = IterateMajorization(map, SquaredDistanceSum(edges), tolerance,
                                               max_iterations, &x, deadline, zero);
  for (int i = 0; i < n; ++i) (*positions)[i] = Vec2(x(i), x(n + i));
  return stats;
}

double SquaredDistanceSum(const std::vector<GridEdge>& edges) {
  double s = 0.0;
  for (const GridEdge& e : edges) {
    if (e.d > 0.0) s += e.d * e.d;
  }
  return s;
}

double Stress(const std::vector<GridEdge>& edges, const std::vector<Vec2>& x) {
  double s = 0.0;
  for (const GridEdge& e : edges) {
    const double r = e.d - (x[e.i] - x[e.j]).norm();
    s += r * r;
  }
  return s;
}

}  // namespace surfdeform::internal
