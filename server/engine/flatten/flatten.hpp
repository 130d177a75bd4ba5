// Flattening a sampled surface into the plane (Ma & Lin 1988).
//
// Objective (the paper's appendix): the stress
//   C = sum_i sum_{j in Omega_i} (d_ij - |X_i - X_j|)^2
// over the flat positions X of the nu x nv samples, Omega_i being the samples
// within Chebyshev grid range r of i and d_ij their distance on the surface
// (see surface_distance.hpp). Units are the surface's own.
//
// Methods:
//  - kMajorization (default): stress majorization, the Guttman transform of
//    SMACOF (de Leeuw 1977; Gansner, Koren & North 2004) with unit weights. The
//    weighted Laplacian of the neighbourhood graph depends only on (nu, nv, r),
//    so it is factored once (exactly, by two small dense eigendecompositions:
//    see flatten_solvers.hpp) and reused by every iteration, by every frame of
//    an animation and by every surface with the same grid. Each iteration
//    costs O(n r^2) for B(X) X plus O(n (nu + nv)) for the solve. Anderson
//    acceleration (Walker & Ni 2011) of the fixed-point map cuts the
//    iterations ~4x; a step that would raise the stress falls back to the
//    plain Guttman transform, so the stress never increases.
//  - kPaper: the paper's gradient descent X <- X - rho dC/dX, kept as the
//    baseline every result is compared with. O(n r^2) per iteration, many more
//    iterations.
//  - Analytic cylinder and cone patches are unrolled in closed form (exact), unless
//    exact_developable is false.
//
// The returned sheet is canonical: sample (0, 0) at the origin, the grid edge
// from sample (0, 0) to (1, 0) along +X, and v towards +Y (positive
// orientation). Guarantee: a sheet is returned only without folded cells; a
// folded (inverted or non-convex) cell would make the inverse map ambiguous, so
// such a result is an error (kNotConverged) that says how many cells folded.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "base/cancel_flag.hpp"
#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/flat_sheet.hpp"
#include "engine/common/geometry_types.hpp"
#include "engine/distance/surface_distance.hpp"
#include "engine/flatten/flatten_settings.hpp"
#include "engine/flatten/sheet_trend.hpp"
#include "engine/surface/sample_grid.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

// A flattening as the engine runs it: the request's settings and how it
// runs (set by the service from its flags and limits, never by a request).
struct FlattenOptions : FlattenSettings {
  int threads = 0;              // worker threads; 0 = one per core. Results do not depend on it.
  double time_budget_ms = 0.0;  // the solver stops with kLimitExceeded past this; 0 = none
  const CancelFlag* cancel = nullptr;  // raised: the solver stops as at its budget's end
  // A surface given as a mesh: the most vertex pairs within max(range, 3)
  // rings it may have (kLimitExceeded past it, found before they are all
  // listed); 0 = no limit. Set by the service, not by requests.
  size_t max_mesh_pairs = 0;
};

// A surface's samples and the distances between them: what a flattening
// measures before it solves.
struct MeasuredGrid {
  SampledGrid grid;
  SurfaceDistances distances;
};

// Keeps what can be reused between solves on the same grid size and range (the
// factored Laplacian) so that the frames of an animation, or many surfaces with
// the same sampling, pay for it once. Not thread-safe: one per thread.
class Flattener {
 public:
  explicit Flattener(FlattenOptions options = {});
  ~Flattener();
  Flattener(Flattener&&) noexcept;
  Flattener& operator=(Flattener&&) noexcept;

  // Flattens `surface` sampled as asked. `warm_start`, when given and of the
  // same grid size, is the starting layout (e.g. the previous animation frame
  // or edit). `warm_paths`, when given, are the paths an earlier measurement
  // of the surface's previous version followed (same grid, range and
  // lattice): the distances are measured from them
  // (RefollowSurfaceDistances). The paths this measurement follows go to
  // `*paths_out` when given, for the next edit (some 60 bytes a pair: the
  // service keeps them for surfaces made to be edited). `warm_trend`, when
  // given, is how the warm start changed over its own edit
  // (TrendBetween): the solve starts from the warm start moved on along it
  // as far as this surface's samples moved along its samples' change, if
  // that layout's stress is the lower (non-periodic sheets only).
  Result<FlatSheet> Flatten(const Surface& surface, const SamplingOptions& sampling,
                            const FlatSheet* warm_start = nullptr,
                            const DistancePaths* warm_paths = nullptr,
                            DistancePaths* paths_out = nullptr,
                            const SheetTrend* warm_trend = nullptr);
  // The same with the samples and their distances measured already
  // (FlattenDistances with these options; an animation measures its frames'
  // in parallel). quality.distance_ms is then theirs.
  Result<FlatSheet> Flatten(const Surface& surface, const FlatSheet* warm_start,
                            MeasuredGrid measured);

  const FlattenOptions& options() const { return options_; }
  // New options for the next solves (an animation's time budget, frame by
  // frame); what is cached stays valid.
  void set_options(const FlattenOptions& options) { options_ = options; }

 private:
  Result<FlatSheet> Solve(const Surface& surface, SampledGrid grid, const FlatSheet* warm_start,
                          const SheetTrend* warm_trend, SurfaceDistances dist, double distance_ms,
                          std::chrono::steady_clock::time_point t0);

  struct Cache;
  FlattenOptions options_;
  std::unique_ptr<Cache> cache_;
};

// Whether `surface` is flattened periodic in u with these options on a grid
// `nu` samples wide: the columns of one period (nu - 1) when the
// surface closes in u (Surface::ClosedInU), is not unrolled in closed form,
// is flattened by majorization and the period leaves room for the
// neighbourhood (nu - 1 >= 2 max(range, 3) + 1); else 0, and the sheet has a
// seam no model crosses. The stress then counts the pairs across the seam,
// and the period is solved with the sheet.
int PeriodicColumns(const Surface& surface, int nu, const FlattenOptions& options);
// The same in v (Surface::ClosedInV): the rows of one period, or 0.
int PeriodicRows(const Surface& surface, int nv, const FlattenOptions& options);

// The samples and surface distances a flattening with these options measures
// (over the solve's range and at least r = 3, for the quality measures; a
// periodic flattening's on the grid continued past the seam by that range), on
// `threads` threads (0: options.threads); the paths followed go to `paths` if
// given.
Result<MeasuredGrid> FlattenDistances(const Surface& surface, const SamplingOptions& sampling,
                                      const FlattenOptions& options, int threads = 0,
                                      DistancePaths* paths = nullptr);

// The same measured along a blend of the paths that such measurements of
// nearby surfaces followed (RemeasureSurfaceDistances): a frame of an
// animation between frames measured afresh.
Result<MeasuredGrid> FlattenDistancesBetween(const Surface& surface,
                                             const SamplingOptions& sampling,
                                             const FlattenOptions& options,
                                             std::span<const PathBlend> blends, int threads = 0);

// One-shot convenience: a fresh Flattener per call.
Result<FlatSheet> FlattenSurface(const Surface& surface, const SamplingOptions& sampling,
                                 const FlattenOptions& options = {});

Status ValidateFlattenOptions(const FlattenOptions& options);

// The quality of any layout `flat` of the nu x nv grid whose distances are
// `distances` (another method's, for comparisons), on the flattening's own
// terms: `flat` is moved to the canonical position first (sample (0, 0) at
// the origin, u along +X), then its stress, edge error, area ratios and
// folded cells are measured.
FlattenQuality MeasureLayout(const SurfaceDistances& distances, int nu, int nv,
                             std::vector<Vec2>* flat);

}  // namespace surfdeform
