// Stress majorization (SMACOF) with unit weights; see flatten.hpp.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "engine/flatten_solvers.hpp"

namespace surfdeform::internal {

namespace {

// Eigen-decomposition of S = D^-1/2 B D^-1/2 for the band matrix B of ones
// within distance r (see LaplacianFactor).
void BandSpectrum(int n, int r, Eigen::MatrixXd* w, Eigen::VectorXd* mu, Eigen::VectorXd* rs) {
  Eigen::MatrixXd s(n, n);
  rs->resize(n);
  for (int i = 0; i < n; ++i) {
    const int count = std::min(n - 1, i + r) - std::max(0, i - r) + 1;
    (*rs)(i) = 1.0 / std::sqrt(static_cast<double>(count));
  }
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) s(i, k) = std::abs(i - k) <= r ? (*rs)(i) * (*rs)(k) : 0.0;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s);
  *w = eig.eigenvectors();
  *mu = eig.eigenvalues();
}

}  // namespace

std::unique_ptr<LaplacianFactor> FactorLaplacian(int nu, int nv, int range) {
  auto f = std::make_unique<LaplacianFactor>();
  f->nu = nu;
  f->nv = nv;
  f->range = range;
  Eigen::VectorXd mu_u, mu_v;
  BandSpectrum(nu, range, &f->wu, &mu_u, &f->ru);
  BandSpectrum(nv, range, &f->wv, &mu_v, &f->rv);
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

void LaplacianFactor::Solve(Eigen::MatrixXd* bx, Eigen::MatrixXd* by) const {
  for (Eigen::MatrixXd* b : {bx, by}) {
    Eigen::MatrixXd y = ru.asDiagonal() * (*b) * rv.asDiagonal();
    Eigen::MatrixXd z = wu.transpose() * y * wv;
    z.array() *= inverse_spectrum.array();
    y.noalias() = wu * z * wv.transpose();
    *b = ru.asDiagonal() * y * rv.asDiagonal();
  }
}

SolveStats SolveMajorization(const LaplacianFactor& factor, const std::vector<GridEdge>& edges,
                             double tolerance, int max_iterations, std::vector<Vec2>* x) {
  const int n = static_cast<int>(x->size());
  std::vector<Vec2>& pos = *x;
  Eigen::MatrixXd bx(factor.nu, factor.nv), by(factor.nu, factor.nv);
  SolveStats stats;
  double stress = Stress(edges, pos);
  const double total = SquaredDistanceSum(edges);
  for (int it = 0; it < max_iterations; ++it) {
    // Guttman transform: L X' = B(X) X, (B(X) X)_i = sum_j d_ij / |X_i - X_j| (X_i - X_j).
    bx.setZero();
    by.setZero();
    double* px = bx.data();
    double* py = by.data();
    for (const GridEdge& e : edges) {
      const Vec2 diff = pos[e.i] - pos[e.j];
      const double len = diff.norm();
      if (!(len > 0.0)) continue;
      const Vec2 c = (e.d / len) * diff;
      px[e.i] += c.x();
      py[e.i] += c.y();
      px[e.j] -= c.x();
      py[e.j] -= c.y();
    }
    factor.Solve(&bx, &by);
    for (int i = 0; i < n; ++i) pos[i] = Vec2(px[i], py[i]);
    const double next = Stress(edges, pos);
    stats.iterations = it + 1;
    const bool settled = StressSettled(stress, next, tolerance, total);
    stress = next;
    if (settled) {
      stats.converged = true;
      break;
    }
  }
  return stats;
}

double SquaredDistanceSum(const std::vector<GridEdge>& edges) {
  double s = 0.0;
  for (const GridEdge& e : edges) s += e.d * e.d;
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
