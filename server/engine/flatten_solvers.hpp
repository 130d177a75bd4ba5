// Internal to the flattening: the solvers and the quality measures, on a grid
// whose surface distances are known. Not part of the engine's public surface.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <memory>
#include <vector>

#include "engine/flatten.hpp"
#include "engine/surface_distance.hpp"

namespace surfdeform::internal {

struct SolveStats {
  int iterations = 0;
  bool converged = false;
  bool out_of_time = false;  // stopped at the deadline
};

using Deadline = std::chrono::steady_clock::time_point;
inline constexpr Deadline kNoDeadline = Deadline::max();

// The stopping rule shared by the iterative solvers: C changed by at most
// `tolerance` of itself in the last iteration, or reached zero (relative to
// sum d_ij^2 = `scale`).
inline bool StressSettled(double before, double after, double tolerance, double scale) {
  const double change = before > after ? before - after : after - before;
  return change <= tolerance * before || after <= 1e-28 * scale;
}

// sum over edges of d_ij^2.
double SquaredDistanceSum(const std::vector<GridEdge>& edges);

// The unit-weight Laplacian L of the neighbourhood graph (samples within
// Chebyshev grid range r), "factored" exactly: with B_n the n x n band matrix of
// ones for |i - k| <= r and D_n = diag(row sums of B_n), the graph adjacency is
// B_v (x) B_u - I and the degrees are diag(D_v (x) D_u) - 1, so
//   L = D_v (x) D_u - B_v (x) B_u = D^1/2 (I - S_v (x) S_u) D^1/2,
// S_n = D_n^-1/2 B_n D_n^-1/2 = W_n M_n W_n^T. Two dense symmetric
// eigendecompositions (nu x nu and nv x nv) diagonalise L, and a solve is four
// small matrix products: O(nu nv (nu + nv)) with no fill-in. Depends only on
// (nu, nv, range).
class LaplacianFactor {
 public:
  int nu = 0, nv = 0, range = 0;
  Eigen::MatrixXd wu, wv;            // eigenvectors of S_u, S_v
  Eigen::VectorXd ru, rv;            // D^-1/2 diagonals
  Eigen::MatrixXd inverse_spectrum;  // 1 / (1 - mu_u(a) mu_v(b)); 0 on the constant mode
  // Solves L x = b in place for sum-zero right-hand sides given as the nu x nv
  // blocks [b_x b_y] of a nu x 2nv matrix (one per coordinate); the constant
  // component of x is zero. With threads > 1 the coordinates are solved in
  // parallel (same result).
  void Solve(Eigen::MatrixXd* b, int threads) const;

 private:
  void SolveBlock(Eigen::Ref<Eigen::MatrixXd> y, Eigen::MatrixXd* scratch) const;
};

// The solvers take the edges of the neighbourhood they minimise over (ring <= r).

std::unique_ptr<LaplacianFactor> FactorLaplacian(int nu, int nv, int range);

// Stress majorization from the layout in `x` (n points), in place.
// threads: workers for the large passes (0 = one per core); results do not
// depend on it.
SolveStats SolveMajorization(const LaplacianFactor& factor, const std::vector<GridEdge>& edges,
                             double tolerance, int max_iterations, int threads,
                             std::vector<Vec2>* x, Deadline deadline = kNoDeadline);

// The paper's gradient descent from the layout in `x`, in place. step <= 0: automatic.
SolveStats SolvePaperDescent(const std::vector<GridEdge>& edges, double step, double tolerance,
                             int max_iterations, std::vector<Vec2>* x,
                             Deadline deadline = kNoDeadline);

// Half the paper's C: sum over the edges (each pair once) of (d - |X_i - X_j|)^2.
double Stress(const std::vector<GridEdge>& edges, const std::vector<Vec2>& x);

// Rigid motion (and reflection if needed) to the canonical frame; see
// flatten.hpp. Reports it as canonical = linear * old + offset when asked.
void Canonicalize(int nu, int nv, std::vector<Vec2>* x, Eigen::Matrix2d* linear = nullptr,
                  Vec2* offset = nullptr);

// Fills stress, edge error, area ratios and folded cells.
void MeasureQuality(const SurfaceDistances& dist, const std::vector<Vec2>& x,
                    FlattenQuality* quality);

}  // namespace surfdeform::internal
