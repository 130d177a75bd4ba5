// Internal to the flattening: the solvers and the quality measures, on a grid
// whose surface distances are known. Not part of the engine's public surface.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <functional>
#include <memory>
#include <vector>

#include "engine/common/elapsed.hpp"
#include "engine/distance/surface_distance.hpp"
#include "engine/flatten/flatten.hpp"

namespace surfdeform::internal {

struct SolveStats {
  int iterations = 0;
  bool converged = false;
  bool out_of_time = false;  // stopped at the deadline
};

using surfdeform::Deadline;
inline const Deadline kNoDeadline{};

// The stopping rule shared by the iterative solvers: C changed by at most
// `tolerance` of itself in the last iteration, or reached zero (relative to
// sum d_ij^2 = `scale`; below `zero` of it).
inline bool StressSettled(double before, double after, double tolerance, double scale,
                          double zero = 1e-28) {
  const double change = before > after ? before - after : after - before;
  return change <= tolerance * before || after <= zero * scale;
}

// B(X) X for the Guttman transform, (B(X) X)_i = sum_j d_ij / |X_i - X_j| (X_i - X_j),
// over edges [begin, end) of n points, added into `rhs` (x block then y
// block, like X); returns their stress. An edge of negative d is free: it
// takes its current length (d_ij = |X_i - X_j|) and adds no stress, so the
// fixed point is the stress's over the other edges (a mesh frame's pair
// whose distance could not be measured keeps the factored Laplacian valid).
// SquaredDistanceSum leaves such edges out.
double GuttmanTerms(const std::vector<GridEdge>& edges, size_t begin, size_t end,
                    const Eigen::VectorXd& x, int n, Eigen::VectorXd* rhs);

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
// (nu, nv, range). With periodic_u, the neighbourhood wraps round in u
// (samples within circular distance r; nu >= 2 r + 1): B_u is then the
// circulant band, and D_u = (2 r + 1) I; likewise periodic_v.
class LaplacianFactor {
 public:
  int nu = 0, nv = 0, range = 0;
  bool periodic_u = false, periodic_v = false;
  Eigen::MatrixXd wu, wv;            // eigenvectors of S_u, S_v
  Eigen::VectorXd ru, rv;            // D^-1/2 diagonals
  Eigen::MatrixXd inverse_spectrum;  // 1 / (1 - mu_u(a) mu_v(b)); 0 on the constant mode
  // Solves L x = b in place for sum-zero right-hand sides given as the nu x nv
  // blocks [b_x b_y] of a nu x 2nv matrix (one per coordinate); the constant
  // component of x is zero. With threads > 1 the coordinates are solved in
  // parallel (same result).
  void Solve(Eigen::Ref<Eigen::MatrixXd> b, int threads) const;

 private:
  void SolveBlock(Eigen::Ref<Eigen::MatrixXd> y, Eigen::MatrixXd* scratch) const;
};

// The solvers take the edges of the neighbourhood they minimise over (ring <= r).

std::unique_ptr<LaplacianFactor> FactorLaplacian(int nu, int nv, int range, bool periodic_u = false,
                                                 bool periodic_v = false);

// One step of stress majorization as a map of the unknowns X (a vector):
// right_hand_side fills b = B(X) X (sized like X) and returns the stress of
// X; solve replaces b by the Guttman transform G(X) = L^+ b.
struct MajorizationMap {
  std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd* b)> right_hand_side;
  std::function<void(Eigen::VectorXd* b)> solve;
};

// Iterates X <- G(X) from `x`, in place, with safeguarded Anderson
// acceleration, until the stress settles (StressSettled with `total` =
// sum d_ij^2), max_iterations or the deadline.
// `zero`: the stress, as a fraction of `total`, that counts as none.
SolveStats IterateMajorization(const MajorizationMap& map, double total, double tolerance,
                               int max_iterations, Eigen::VectorXd* x, Deadline deadline,
                               double zero = 1e-28);

// Sums a right-hand side over [0, count) items split into partial sums, one
// per thread for large sets (50000 items and more), added in a fixed order:
// the result does not depend on timing. `terms(begin, end, out)` adds its
// items' terms into `out` (zeroed, sized like the right-hand side) and
// returns their stress.
class ChunkedGuttmanSum {
 public:
  using Terms = std::function<double(int begin, int end, Eigen::VectorXd* out)>;
  ChunkedGuttmanSum(size_t items, int size, int threads);
  double Sum(int count, Eigen::VectorXd* rhs, const Terms& terms);

 private:
  int chunks_;
  std::vector<Eigen::VectorXd> partial_;
  std::vector<double> stress_;
};

// Stress majorization over `edges` from the layout in `positions`, in place,
// with `solve` the Guttman transform's solve (b -> L^+ b, b the x block then
// the y block): the grid's solver and the mesh's differ only there.
// IterateMajorization's rules (`zero` as there); threads for the right-hand
// sides (0 = one per core), results independent of them.
SolveStats MajorizeLayout(const std::function<void(Eigen::VectorXd*)>& solve,
                          const std::vector<GridEdge>& edges, double tolerance, int max_iterations,
                          int threads, std::vector<Vec2>* positions, Deadline deadline,
                          double zero = 1e-28);

// Stress majorization from the layout in `x` (n points), in place.
// threads: workers for the large passes (0 = one per core); results do not
// depend on it.
SolveStats SolveMajorization(const LaplacianFactor& factor, const std::vector<GridEdge>& edges,
                             double tolerance, int max_iterations, int threads,
                             std::vector<Vec2>* x, Deadline deadline = kNoDeadline);

// A pair of nodes of a periodic sheet, whose flat difference is
// Y_j + shift_u T_u + shift_v T_v - Y_i (T_u, T_v: the periods; shifts -1,
// 0 or 1, and 0 in a direction that is not periodic).
struct SeamEdge {
  int i = 0;
  int j = 0;
  int shift_u = 0;
  int shift_v = 0;
  int ring = 0;
  double d = 0.0;
};

// The columns and rows of one period of a periodic grid: period_u (0: not
// periodic in u, the grid's nu columns) and period_v (0: nv rows).
struct GridPeriods {
  int period_u = 0;
  int period_v = 0;
  int nu = 0;  // the grid's samples
  int nv = 0;
  int node_columns() const { return period_u > 0 ? period_u : nu; }
  int node_rows() const { return period_v > 0 ? period_v : nv; }
};

// The distinct pairs of a periodic grid from the distances measured on it
// continued past its seams (`extended`: a period and the range in each
// periodic direction; column c and c + period_u the same samples, likewise
// rows): each pair once, the one whose least column is in [0, period_u)
// and least row in [0, period_v) where periodic; nodes i + node_columns j.
// Only pairs of rings up to max_ring.
std::vector<SeamEdge> PeriodicEdges(const SurfaceDistances& extended, const GridPeriods& periods,
                                    int max_ring);

// Stress majorization of a periodic sheet (periodic_majorization.cpp): the
// node_columns x node_rows nodes `nodes` (the factor's grid, periodic as
// `periods`) and the periods T_u, T_v (those of the periodic directions),
// from their values, in place.
SolveStats SolvePeriodicMajorization(const LaplacianFactor& factor, const GridPeriods& periods,
                                     const std::vector<SeamEdge>& edges, double tolerance,
                                     int max_iterations, int threads, std::vector<Vec2>* nodes,
                                     Vec2* period_u, Vec2* period_v,
                                     Deadline deadline = kNoDeadline);

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

// Fills stress, edge error, area ratios and folded cells: over the first
// `cell_columns` columns and `cell_rows` rows of cells (-1: all).
void MeasureQuality(const SurfaceDistances& dist, const std::vector<Vec2>& x,
                    FlattenQuality* quality, int cell_columns = -1, int cell_rows = -1);

}  // namespace surfdeform::internal
