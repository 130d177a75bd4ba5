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
#include "engine/flatten_settings.hpp"
#include "engine/geometry_types.hpp"
#include "engine/sample_grid.hpp"
#include "engine/sheet_trend.hpp"
#include "engine/surface.hpp"
#include "engine/surface_distance.hpp"

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

// Quality of a flat sheet. Stress and the other measures are always taken over
// the r = 3 neighbourhood, whatever range the solve used, so results compare.
struct FlattenQuality {
  double stress = 0.0;          // sqrt(C / sum d_ij^2), dimensionless
  double max_edge_error = 0.0;  // max over grid edges of | |X_i - X_j| - d_ij | / d_ij
  double area_ratio_min = 0.0;  // min over cells of flat area / surface area
  double area_ratio_max = 0.0;
  int folded_cells = 0;  // cells whose flat quad is inverted or not convex
  int iterations = 0;
  bool converged = false;    // reached the tolerance before max_iterations
  double distance_ms = 0.0;  // computing d_ij
  // Pairs measured from the paths an earlier measurement followed
  // (Flattener::Flatten's warm_paths) rather than relaxed afresh; 0 for a
  // cold measurement.
  int refollowed_paths = 0;
  // The step along the warm start's trend that the solve started from
  // (sheet_trend.hpp); 0 when it started from the warm start itself.
  double extrapolated = 0.0;
  double solve_ms = 0.0;  // the solver itself (factorisation included)
  double total_ms = 0.0;  // sampling, distances, solve and quality
};

struct FlatSheet {
  int nu = 0;
  int nv = 0;
  std::vector<Vec3> points;   // surface samples, i + nu * j
  std::vector<Vec3> normals;  // unit surface normals at the samples
  std::vector<Vec2> flat;     // flat positions of the samples, canonical frame
  std::string method;         // "majorization", "paper" or "exact"
  // canonical = frame_linear * solver's + frame_offset (a rotation, and a
  // reflection if the solver's layout was mirrored). With method "exact", maps
  // Surface::ExactUnrolling into this sheet.
  Eigen::Matrix2d frame_linear = Eigen::Matrix2d::Identity();
  Vec2 frame_offset = Vec2::Zero();
  // A sheet flattened periodic in u (PeriodicColumns > 0): its period T, in
  // the canonical frame. Flat points p and p + T are the same surface point;
  // column nu - 1 (the seam again) is column 0 + T. Zero otherwise.
  Vec2 period_u = Vec2::Zero();
  // The same in v (PeriodicRows > 0): row nv - 1 is row 0 + period_v. A
  // surface periodic both ways (a whole torus) is a flat torus.
  Vec2 period_v = Vec2::Zero();
  FlattenQuality quality;
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
// `nu` samples wide (issue #36): the columns of one period (nu - 1) when the
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
