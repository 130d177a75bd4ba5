// Distances on the surface between grid samples: the d_ij of Ma & Lin's stress.
//
// d_ij is the length of the shortest path on the surface between samples i and
// j, for every pair within Chebyshev grid range r (|di| <= r and |dj| <= r).
// The length of the straight parameter-space segment between them is only an
// upper bound (on a cone patch it overestimates by ~1e-2 relative at 16x16,
// r = 3). Each pair is measured in one of two ways:
//   0. Directly: the normal section through i and j (nearly the geodesic: they
//      differ at fifth order in the length) is measured from the chord and its
//      projections on the tangent planes at i and j, as an arc whose turn phi
//      they give. Its error stays below 0.01 phi^4, so this is used where the
//      chord turns by less than 0.03 rad (~1e-8 relative): on fine grids, and
//      along flat directions. The other pairs follow a path:
//   1. The surface and its first derivatives are evaluated once on a lattice
//      `lattice_factor` times finer than the sample grid; the straight segment
//      from i to j runs through lattice points, and its length is summed
//      sub-segment by sub-segment from the chord and the turning of the tangent
//      (exact for circular arcs, O(h^4) for any smooth arc).
//   2. Gauss-Newton steps on the discrete path energy sum |P_{k+1} - P_k|^2
//      move the interior points of the path (a block-tridiagonal 2x2 solve per
//      step); the relaxed path is measured the same way. Its parameters may leave
//      [0, 1]^2 slightly: surfaces continue smoothly past their borders, so a
//      path by a concave border is measured as on the continued surface (on a
//      cone this is exactly the distance in the unrolled plane).
// Each reported distance is the length of a real path on the surface, so it is
// never below the geodesic distance; on planes and cylinders the straight path
// already is the geodesic and no relaxation is done.
//
// Cost: (f (nu-1) + 1)(f (nv-1) + 1) derivative evaluations for the lattice,
// plus up to (f * r - 1) * steps evaluations per pair whose path bends.
#pragma once

#include <chrono>
#include <span>
#include <vector>

#include "base/cancel_flag.hpp"
#include "base/status.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

struct DistanceOptions {
  int range = 3;           // Chebyshev grid range r, 1..8
  int lattice_factor = 0;  // lattice points per grid cell side; 0 = automatic (4, or 2 above 64)
  int relax_steps = 2;     // Gauss-Newton steps per path; 0 = straight segments only
  int threads = 0;         // worker threads; 0 = one per core. Results do not depend on it.
  // A time budget, in ms from `started` (0 = none): past it the work stops
  // between rows of pairs with kDeadlineExceeded, the budget and the time
  // spent since `started` attached.
  double time_budget_ms = 0.0;
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  const CancelFlag* cancel = nullptr;  // raised: the work stops as at its budget's end
};

// One pair of samples (i < j in index order) with its surface distance.
struct GridEdge {
  int i = 0;
  int j = 0;
  int di = 0;    // grid offset of j from i along u
  int dj = 0;    // grid offset of j from i along v
  int ring = 0;  // Chebyshev grid distance max(|di|, |dj|), 1..range
  double d = 0.0;
};

struct SurfaceDistances {
  int nu = 0;
  int nv = 0;
  int range = 0;
  std::vector<GridEdge> edges;  // grouped by offset; every pair once
  int direct_pairs = 0;         // pairs measured directly (step 0)
  int relaxed_paths = 0;        // pairs whose path was relaxed off the straight segment
  int reused_paths = 0;         // pairs measured along another measurement's path (Remeasure...)
  // Area on the surface of each grid cell (i, j), index i + (nu - 1) * j, by the
  // trapezoidal rule over the lattice.
  std::vector<double> cell_areas;
};

// The paths a measurement followed: for each edge (in the order of
// SurfaceDistances::edges) measured along a path, the parameters of the
// path's interior points, to measure a nearby surface along them again.
struct DistancePaths {
  int nu = 0;
  int nv = 0;
  int range = 0;
  int lattice_factor = 0;
  std::vector<double> turn;  // per edge: how far its chord turned (radians)
  std::vector<Vec2> q;       // per edge, lattice_factor - 1 interior points

  // Whether the edge was measured along a path (its chord turned too much to
  // be measured directly); its q hold the path only then.
  bool Followed(size_t edge) const;
  // What they take in memory.
  size_t bytes() const {
    return sizeof(*this) + turn.size() * sizeof(double) + q.size() * sizeof(Vec2);
  }
};

// The lattice factor a measurement of an nu x nv grid uses for `given`
// (DistanceOptions::lattice_factor; 0: automatic), and the points of its
// lattice (each some 200 bytes while the distances are measured): for the
// memory a flattening takes, before it runs.
int DistanceLatticeFactor(int nu, int nv, int given);
size_t DistanceLatticePoints(int nu, int nv, int given);

// Measures the distances; fills `paths`, when given, with the paths followed.
Result<SurfaceDistances> ComputeSurfaceDistances(const Surface& surface, int nu, int nv,
                                                 const DistanceOptions& options,
                                                 DistancePaths* paths = nullptr);

// Measures `surface` along the paths that a measurement of a nearby surface
// followed (an earlier frame of an animation, with the same parameterisation):
// each pair that the other measured along a path, and that still turns too
// much to be measured directly (not looked at where every path's chord turned
// by twice that), is measured along the same parameter path on
// this surface, without relaxing it again. That is the length of a real path
// on this surface, so still never below the geodesic distance; and since the
// relaxed path was nearly a geodesic, its length differs from a path relaxed
// afresh at second order only in how far the geodesic moved. Other pairs are
// measured as ComputeSurfaceDistances measures them. Costs one first-order
// evaluation per interior path point, instead of a relaxation per pair.
// The parameters of the paths followed are blended as sum_i weight_i q_i (the
// weights add up to 1: e.g. 1 - s and s between two frames). Each pair is
// measured along the first of the blends whose paths all followed it.
struct WeightedPaths {
  const DistancePaths* paths = nullptr;
  double weight = 0.0;
};
using PathBlend = std::span<const WeightedPaths>;
Result<SurfaceDistances> RemeasureSurfaceDistances(const Surface& surface,
                                                   std::span<const PathBlend> blends,
                                                   const DistanceOptions& options);

// Measures `surface` starting from the paths that a measurement of an earlier
// version of it followed (a live edit of the same surface: same kind, grid
// and parameterisation), and fills `next`, when given, with the paths this
// one followed, for the edit after it. Each pair the earlier measurement
// followed a path for, and whose chord still turns too much to be measured
// directly, is measured along that path on this surface, then along the
// path moved by one Gauss-Newton step taken from those exact evaluations;
// the shorter of the two counts and is kept. Both are lengths of real paths
// on this surface, so never below the geodesic distance; since the earlier
// path was relaxed on a nearby surface, the step lands within second order
// of a path relaxed afresh, and the paths do not drift from edit to edit.
// Other pairs are measured as ComputeSurfaceDistances measures them. Costs
// two first-order evaluations per path point in place of a relaxation from
// the straight segment.
Result<SurfaceDistances> RefollowSurfaceDistances(const Surface& surface,
                                                  const DistancePaths& previous,
                                                  const DistanceOptions& options,
                                                  DistancePaths* next = nullptr);

}  // namespace surfdeform
