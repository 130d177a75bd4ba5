// The paper's gradient descent on Ma & Lin's stress (appendix of the paper):
//   X_i <- X_i - rho dC/dX_i,  C = sum_i sum_{j in Omega_i} (d_ij - |X_i - X_j|)^2,
// so dC/dX_i = 4 sum_{j in Omega_i} (|X_i - X_j| - d_ij) (X_i - X_j) / |X_i - X_j|
// (each pair appears in Omega_i and in Omega_j). The paper leaves rho "a small
// positive number": the automatic value 1 / (8 max_i |Omega_i|) keeps rho times
// the largest curvature of C below 1, the classic bound for a stable descent.
// Stopping rule: C decreases by less than `tolerance` of itself in an iteration.
#include <algorithm>
#include <cmath>

#include "engine/flatten/flatten_solvers.hpp"

namespace surfdeform::internal {

SolveStats SolvePaperDescent(const std::vector<GridEdge>& edges, double step, double tolerance,
                             int max_iterations, std::vector<Vec2>* x, Deadline deadline) {
  std::vector<Vec2>& pos = *x;
  const int n = static_cast<int>(pos.size());
  if (!(step > 0.0)) {
    std::vector<int> degree(n, 0);
    for (const GridEdge& e : edges) {
      ++degree[e.i];
      ++degree[e.j];
    }
    const int max_degree = std::max(1, *std::max_element(degree.begin(), degree.end()));
    step = 1.0 / (8.0 * max_degree);
  }
  std::vector<Vec2> grad(n);
  SolveStats stats;
  const double total = SquaredDistanceSum(edges);
  double previous = 0.0;
  for (int it = 0;; ++it) {
    // The gradient pass also measures the stress of X, which decides whether to go on.
    std::fill(grad.begin(), grad.end(), Vec2::Zero());
    double stress = 0.0;
    for (const GridEdge& e : edges) {
      const Vec2 diff = pos[e.i] - pos[e.j];
      const double len = diff.norm();
      stress += (e.d - len) * (e.d - len);
      if (!(len > 0.0)) continue;
      const Vec2 g = (4.0 * (len - e.d) / len) * diff;
      grad[e.i] += g;
      grad[e.j] -= g;
    }
    if (it > 0 && StressSettled(previous, stress, tolerance, total)) {
      stats.converged = true;
      break;
    }
    if (it == max_iterations || !std::isfinite(stress)) break;
    if (deadline.Passed()) {
      stats.out_of_time = true;
      break;
    }
    previous = stress;
    for (int i = 0; i < n; ++i) pos[i] -= step * grad[i];
    stats.iterations = it + 1;
  }
  return stats;
}

}  // namespace surfdeform::internal
