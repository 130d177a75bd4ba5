#include "engine/flatten/flatten.hpp"

#include <algorithm>
#include <chrono>
#include <span>
#include <string>

#include "engine/common/elapsed.hpp"
#include "engine/distance/surface_distance.hpp"
#include "engine/flatten/flatten_solvers.hpp"
#include "engine/flatten/mesh_flatten.hpp"
#include "engine/flatten/seam_extension.hpp"

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;
using Vec2i = Eigen::Vector2i;

// Starting layout: the parameter grid scaled by the mean surface length of the
// u and v grid lines, so that it has the sheet's size.
std::vector<Vec2> ScaledParameterLayout(const SurfaceDistances& dist) {
  double su = 0.0, sv = 0.0;
  for (const GridEdge& e : dist.edges) {
    if (e.ring != 1) continue;
    if (e.dj == 0) su += e.d;
    if (e.di == 0) sv += e.d;
  }
  const int nu = dist.nu, nv = dist.nv;
  const double cell_u = su / ((nu - 1) * nv);
  const double cell_v = sv / (nu * (nv - 1));
  std::vector<Vec2> x(static_cast<size_t>(nu) * nv);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) x[i + nu * j] = Vec2(i * cell_u, j * cell_v);
  }
  return x;
}

// The warm start `x` (warm's layout) moved on along `trend` as far as the
// samples `now` moved along its samples' change from warm's, where that
// lowers the stress over `edges`; returns the step taken (0: none).
double ExtrapolateStart(const FlatSheet& warm, const SheetTrend& trend, std::span<const Vec3> now,
                        const std::vector<GridEdge>& edges, std::vector<Vec2>* x) {
  const double step = TrendStep(trend, warm.points, now);
  if (step == 0.0) return 0.0;
  std::vector<Vec2> ahead = Extrapolated(*x, trend, step);
  if (!(internal::Stress(edges, ahead) < internal::Stress(edges, *x))) return 0.0;
  *x = std::move(ahead);
  return step;
}

// The quality of a periodic sheet (nu x nv; column nu - 1 the seam in u
// again where periodic in u, row nv - 1 likewise) over every pair and cell
// of one period, those across the seams included: measured on the grid
// continued past them, as its distances were.
void MeasurePeriodicQuality(const SurfaceDistances& continued, const internal::GridPeriods& g,
                            const std::vector<Vec2>& x, const Vec2& period_u, const Vec2& period_v,
                            FlattenQuality* quality) {
  const int pu = g.period_u, pv = g.period_v, columns = continued.nu, rows = continued.nv;
  std::vector<Vec2> xc(static_cast<size_t>(columns) * rows);
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < columns; ++i) {
      const int ku = pu > 0 ? i / pu : 0, kv = pv > 0 ? j / pv : 0;
      xc[i + columns * j] = x[(i - ku * pu) + g.nu * (j - kv * pv)] + ku * period_u + kv * period_v;
    }
  }
  SurfaceDistances once = continued;  // each pair once: its least column and row in the period
  std::erase_if(once.edges, [&](const GridEdge& e) {
    return (pu > 0 && std::min(e.i % columns, e.j % columns) >= pu) ||
           (pv > 0 && std::min(e.i / columns, e.j / columns) >= pv);
  });
  internal::MeasureQuality(once, xc, quality, pu > 0 ? pu : -1, pv > 0 ? pv : -1);
}

}  // namespace

const char* FlattenMethodName(FlattenMethod method) {
  const std::string_view name = NameOf<FlattenMethod>(kFlattenMethods, method);
  return name.empty() ? "unknown" : name.data();  // the table's literals end in NUL
}

Status ValidateFlattenSettings(const FlattenSettings& o) {
  if (o.range < 1 || o.range > 8) {
    return InvalidArgument("must be from 1 to 8, got " + std::to_string(o.range), "range");
  }
  if (!(o.tolerance >= 0.0 && o.tolerance < 1.0)) {
    return InvalidArgument("must be in [0, 1), got " + std::to_string(o.tolerance), "tolerance");
  }
  if (o.max_iterations < 0 || o.max_iterations > 1000000) {
    return InvalidArgument(
        "must be from 0 (automatic) to 1000000, got " + std::to_string(o.max_iterations),
        "max_iterations");
  }
  if (!(o.step >= 0.0 && o.step < 1.0)) {
    return InvalidArgument("must be in [0, 1) (0 = automatic), got " + std::to_string(o.step),
                           "step");
  }
  if (o.lattice_factor < 0 || o.lattice_factor > 16) {
    return InvalidArgument(
        "must be from 0 (automatic) to 16, got " + std::to_string(o.lattice_factor),
        "lattice_factor");
  }
  if (o.relax_steps < 0 || o.relax_steps > 8) {
    return InvalidArgument("must be from 0 to 8, got " + std::to_string(o.relax_steps),
                           "relax_steps");
  }
  return Status::Ok();
}

Status ValidateFlattenOptions(const FlattenOptions& o) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateFlattenSettings(o));
  if (o.threads < 0 || o.threads > 256) {
    return InvalidArgument("must be from 0 (one per core) to 256, got " + std::to_string(o.threads),
                           "threads");
  }
  if (!(o.time_budget_ms >= 0.0 && o.time_budget_ms < 1e12)) {
    return InvalidArgument("must be a non-negative number of milliseconds (0 = none)",
                           "time_budget_ms");
  }
  return Status::Ok();
}

struct Flattener::Cache {
  std::unique_ptr<internal::LaplacianFactor> laplacian;
};

Flattener::Flattener(FlattenOptions options)
    : options_(options), cache_(std::make_unique<Cache>()) {}
Flattener::~Flattener() = default;
Flattener::Flattener(Flattener&&) noexcept = default;
Flattener& Flattener::operator=(Flattener&&) noexcept = default;

namespace {

// `threads` > 0 overrides o.threads.
DistanceOptions DistanceOptionsFor(const FlattenOptions& o, Clock::time_point started,
                                   int threads = 0) {
  DistanceOptions d;
  d.range = std::max(o.range, 3);
  d.lattice_factor = o.lattice_factor;
  d.relax_steps = o.relax_steps;
  d.threads = threads > 0 ? threads : o.threads;
  d.time_budget_ms = o.time_budget_ms;
  d.cancel = o.cancel;
  d.started = started;
  return d;
}

// The periods of a flattening on an nu x nv grid.
internal::GridPeriods PeriodsOf(const Surface& surface, int nu, int nv, const FlattenOptions& o) {
  return {PeriodicColumns(surface, nu, o), PeriodicRows(surface, nv, o), nu, nv};
}

// The columns and rows the distances of a flattening are measured over: the
// grid's, or in a periodic direction, a period and the measured range past
// the seam.
Vec2i MeasuredSize(const internal::GridPeriods& g, const FlattenOptions& o) {
  const int range = std::max(o.range, 3);
  return Vec2i(g.period_u > 0 ? g.period_u + range : g.nu,
               g.period_v > 0 ? g.period_v + range : g.nv);
}

// The surface over the measured grid: continued past its seams.
std::unique_ptr<const Surface> MeasuredSurface(const Surface& surface,
                                               const internal::GridPeriods& g,
                                               const FlattenOptions& o) {
  const Vec2i size = MeasuredSize(g, o);
  const double u_scale = g.period_u > 0 ? static_cast<double>(size.x() - 1) / g.period_u : 1.0;
  const double v_scale = g.period_v > 0 ? static_cast<double>(size.y() - 1) / g.period_v : 1.0;
  return Continued(surface, 0.0, u_scale, 0.0, v_scale);
}

// The distances of the samples of an nu x nv grid (see FlattenDistances),
// from the paths `previous` followed when given and measured on the same
// grid, range and lattice (RefollowSurfaceDistances), else afresh.
Result<SurfaceDistances> MeasureDistances(const Surface& surface, int nu, int nv,
                                          const FlattenOptions& o, const DistanceOptions& d,
                                          DistancePaths* paths,
                                          const DistancePaths* previous = nullptr) {
  const internal::GridPeriods g = PeriodsOf(surface, nu, nv, o);
  const Vec2i size = MeasuredSize(g, o);
  std::unique_ptr<const Surface> continued;
  if (g.period_u > 0 || g.period_v > 0) continued = MeasuredSurface(surface, g, o);
  const Surface& measured = continued ? *continued : surface;
  if (previous != nullptr && previous->nu == size.x() && previous->nv == size.y()) {
    auto refollowed = RefollowSurfaceDistances(measured, *previous, d, paths);
    if (refollowed.ok() || refollowed.status().code() != ErrorCode::kInvalidArgument) {
      return refollowed;
    }
  }
  return ComputeSurfaceDistances(measured, size.x(), size.y(), d, paths);
}

}  // namespace

namespace {

// The samples of one period in a closed direction, when the flattening is
// periodic there (see PeriodicColumns).
int Period(bool closed, const Surface& surface, int n, const FlattenOptions& o) {
  if (!closed || o.method != FlattenMethod::kMajorization) return 0;
  if (o.exact_developable && surface.ExactUnrolling(0.0, 0.0).has_value()) return 0;
  return n - 1 >= 2 * std::max(o.range, 3) + 1 ? n - 1 : 0;
}

}  // namespace

int PeriodicColumns(const Surface& surface, int nu, const FlattenOptions& o) {
  return Period(surface.ClosedInU(), surface, nu, o);
}

int PeriodicRows(const Surface& surface, int nv, const FlattenOptions& o) {
  return Period(surface.ClosedInV(), surface, nv, o);
}

Result<MeasuredGrid> FlattenDistances(const Surface& surface, const SamplingOptions& sampling,
                                      const FlattenOptions& options, int threads,
                                      DistancePaths* paths) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateFlattenOptions(options));
  // The samples first, as Flatten does: a degenerate one is reported as such.
  MeasuredGrid out;
  SURFDEFORM_ASSIGN_OR_RETURN(out.grid, SampleSurface(surface, sampling));
  const DistanceOptions dopt = DistanceOptionsFor(options, Clock::now(), threads);
  SURFDEFORM_ASSIGN_OR_RETURN(
      out.distances, MeasureDistances(surface, out.grid.nu, out.grid.nv, options, dopt, paths));
  return out;
}

Result<MeasuredGrid> FlattenDistancesBetween(const Surface& surface,
                                             const SamplingOptions& sampling,
                                             const FlattenOptions& options,
                                             std::span<const PathBlend> blends, int threads) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateFlattenOptions(options));
  MeasuredGrid out;
  SURFDEFORM_ASSIGN_OR_RETURN(out.grid, SampleSurface(surface, sampling));
  const internal::GridPeriods g = PeriodsOf(surface, out.grid.nu, out.grid.nv, options);
  const Vec2i size = MeasuredSize(g, options);
  if (blends.empty() || blends[0].empty() || size.x() != blends[0][0].paths->nu ||
      size.y() != blends[0][0].paths->nv) {
    return InvalidArgument("the paths were followed on another grid");
  }
  const DistanceOptions dopt = DistanceOptionsFor(options, Clock::now(), threads);
  if (g.period_u == 0 && g.period_v == 0) {
    SURFDEFORM_ASSIGN_OR_RETURN(out.distances, RemeasureSurfaceDistances(surface, blends, dopt));
    return out;
  }
  SURFDEFORM_ASSIGN_OR_RETURN(
      out.distances,
      RemeasureSurfaceDistances(*MeasuredSurface(surface, g, options), blends, dopt));
  return out;
}

namespace {

// The sheet of a surface given as a flattened mesh: its parameter box
// sampled, laid out by its exact unrolling (the flat mesh's own frame,
// moved to the canonical position), with the mesh flattening's quality.
Result<FlatSheet> MeshSheet(const Surface& surface, const FlatMesh& mesh,
                            const SamplingOptions& sampling, Clock::time_point t0) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto grid, SampleSurface(surface, sampling));
  const int nu = grid.nu, nv = grid.nv;
  FlatSheet sheet;
  std::vector<Vec2> x(static_cast<size_t>(nu) * nv);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      x[i + nu * j] = *surface.ExactUnrolling(static_cast<double>(i) / (nu - 1),
                                              static_cast<double>(j) / (nv - 1));
    }
  }
  internal::Canonicalize(nu, nv, &x, &sheet.frame_linear, &sheet.frame_offset);
  sheet.method = FlattenMethodName(FlattenMethod::kMajorization);
  sheet.quality = mesh.quality;
  sheet.nu = nu;
  sheet.nv = nv;
  sheet.points = std::move(grid.points);
  sheet.normals = std::move(grid.normals);
  sheet.flat = std::move(x);
  sheet.quality.total_ms += MsSince(t0);
  return sheet;
}

}  // namespace

Result<FlatSheet> Flattener::Flatten(const Surface& surface, const SamplingOptions& sampling,
                                     const FlatSheet* warm_start, const DistancePaths* warm_paths,
                                     DistancePaths* paths_out, const SheetTrend* warm_trend) {
  const auto t0 = Clock::now();
  SURFDEFORM_RETURN_IF_ERROR(ValidateFlattenOptions(options_));
  if (const FlatMesh* mesh = surface.flat_mesh()) return MeshSheet(surface, *mesh, sampling, t0);
  SURFDEFORM_ASSIGN_OR_RETURN(auto grid, SampleSurface(surface, sampling));
  // Distances over the solve's range and over r = 3 for the quality measures.
  const auto td = Clock::now();
  SURFDEFORM_ASSIGN_OR_RETURN(
      auto dist, MeasureDistances(surface, grid.nu, grid.nv, options_,
                                  DistanceOptionsFor(options_, t0), paths_out, warm_paths));
  const double distance_ms = MsSince(td);
  const int refollowed = dist.reused_paths;
  SURFDEFORM_ASSIGN_OR_RETURN(auto sheet, Solve(surface, std::move(grid), warm_start, warm_trend,
                                                std::move(dist), distance_ms, t0));
  sheet.quality.refollowed_paths = refollowed;
  return sheet;
}

Result<FlatSheet> Flattener::Flatten(const Surface& surface, const FlatSheet* warm_start,
                                     MeasuredGrid measured) {
  const auto t0 = Clock::now();
  SURFDEFORM_RETURN_IF_ERROR(ValidateFlattenOptions(options_));
  const SurfaceDistances& d = measured.distances;
  const Vec2i size =
      MeasuredSize(PeriodsOf(surface, measured.grid.nu, measured.grid.nv, options_), options_);
  if (d.nu != size.x() || d.nv != size.y() || d.range != std::max(options_.range, 3)) {
    return InvalidArgument("the distances were measured for another grid or range");
  }
  return Solve(surface, std::move(measured.grid), warm_start, nullptr,
               std::move(measured.distances), 0.0, t0);
}

Result<FlatSheet> Flattener::Solve(const Surface& surface, SampledGrid grid,
                                   const FlatSheet* warm_start, const SheetTrend* warm_trend,
                                   SurfaceDistances dist, double distance_ms,
                                   std::chrono::steady_clock::time_point t0) {
  const internal::Deadline deadline = DeadlineAfter(t0, options_.time_budget_ms, options_.cancel);
  const int nu = grid.nu, nv = grid.nv;
  const int n = nu * nv;
  FlatSheet sheet;
  sheet.quality.distance_ms = distance_ms;

  const auto ts = Clock::now();
  std::vector<Vec2> x;
  if (options_.exact_developable && surface.ExactUnrolling(0.0, 0.0).has_value()) {
    x.resize(n);
    for (int j = 0; j < nv; ++j) {
      for (int i = 0; i < nu; ++i) {
        x[i + nu * j] = *surface.ExactUnrolling(static_cast<double>(i) / (nu - 1),
                                                static_cast<double>(j) / (nv - 1));
      }
    }
    sheet.method = "exact";
    sheet.quality.converged = true;
  } else {
    internal::SolveStats stats;
    const internal::GridPeriods g = PeriodsOf(surface, nu, nv, options_);
    const bool periodic = g.period_u > 0 || g.period_v > 0;
    const bool warm = warm_start != nullptr && warm_start->nu == nu && warm_start->nv == nv &&
                      warm_start->flat.size() == static_cast<size_t>(n);
    const int max_it = options_.max_iterations > 0                       ? options_.max_iterations
                       : options_.method == FlattenMethod::kMajorization ? 3000
                                                                         : 200000;
    auto& lap = cache_->laplacian;
    if (options_.method == FlattenMethod::kMajorization) {
      const int lap_nu = g.node_columns(), lap_nv = g.node_rows();
      if (!lap || lap->nu != lap_nu || lap->nv != lap_nv || lap->range != options_.range ||
          lap->periodic_u != (g.period_u > 0) || lap->periodic_v != (g.period_v > 0)) {
        lap = internal::FactorLaplacian(lap_nu, lap_nv, options_.range, g.period_u > 0,
                                        g.period_v > 0);
      }
    }
    if (periodic) {
      // The nodes of one period and the periods, from the warm start's or
      // the scaled parameter layout of the continued grid.
      const std::vector<internal::SeamEdge> edges =
          internal::PeriodicEdges(dist, g, options_.range);
      const bool warm_periodic = warm && warm_start->period_u.isZero() == (g.period_u == 0) &&
                                 warm_start->period_v.isZero() == (g.period_v == 0);
      const std::vector<Vec2> start =
          warm_periodic ? warm_start->flat : ScaledParameterLayout(dist);
      const int stride = warm_periodic ? nu : dist.nu;
      const int columns = g.node_columns(), rows = g.node_rows();
      std::vector<Vec2> y(static_cast<size_t>(columns) * rows);
      for (int j = 0; j < rows; ++j) {
        for (int i = 0; i < columns; ++i) y[i + columns * j] = start[i + stride * j];
      }
      if (warm_periodic) {
        sheet.period_u = warm_start->period_u;
        sheet.period_v = warm_start->period_v;
      } else {
        if (g.period_u > 0) sheet.period_u = start[g.period_u] - start[0];
        if (g.period_v > 0) sheet.period_v = start[stride * g.period_v] - start[0];
      }
      stats = internal::SolvePeriodicMajorization(*lap, g, edges, options_.tolerance, max_it,
                                                  options_.threads, &y, &sheet.period_u,
                                                  &sheet.period_v, deadline);
      x.resize(n);
      for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
          const int ku = g.period_u > 0 ? i / g.period_u : 0;
          const int kv = g.period_v > 0 ? j / g.period_v : 0;
          x[i + nu * j] = y[(i - ku * g.period_u) + columns * (j - kv * g.period_v)] +
                          ku * sheet.period_u + kv * sheet.period_v;
        }
      }
    } else {
      std::vector<GridEdge> edges;
      if (options_.range == dist.range) {
        edges = dist.edges;
      } else {
        for (const GridEdge& e : dist.edges) {
          if (e.ring <= options_.range) edges.push_back(e);
        }
      }
      x = warm ? warm_start->flat : ScaledParameterLayout(dist);
      if (warm && warm_trend != nullptr) {
        sheet.quality.extrapolated =
            ExtrapolateStart(*warm_start, *warm_trend, grid.points, edges, &x);
      }
      if (options_.method == FlattenMethod::kMajorization) {
        stats = internal::SolveMajorization(*lap, edges, options_.tolerance, max_it,
                                            options_.threads, &x, deadline);
      } else {
        stats = internal::SolvePaperDescent(edges, options_.step, options_.tolerance, max_it, &x,
                                            deadline);
      }
    }
    if (stats.out_of_time) {
      return Status::DeadlineExceeded(
          "the flattening did not converge within the time budget of " +
              std::to_string(static_cast<long long>(options_.time_budget_ms)) + " ms (" +
              std::to_string(stats.iterations) +
              " iterations); use method \"majorization\", a coarser grid or a looser tolerance",
          "flatten", options_.time_budget_ms, MsSince(t0));
    }
    sheet.method = FlattenMethodName(options_.method);
    sheet.quality.iterations = stats.iterations;
    sheet.quality.converged = stats.converged;
  }
  for (const Vec2& p : x) {
    if (!p.allFinite()) {
      return Status(ErrorCode::kNotConverged,
                    "the flattening diverged (non-finite positions); for method \"paper\" "
                    "choose a smaller step");
    }
  }
  internal::Canonicalize(nu, nv, &x, &sheet.frame_linear, &sheet.frame_offset);
  sheet.period_u = sheet.frame_linear * sheet.period_u;
  sheet.period_v = sheet.frame_linear * sheet.period_v;
  sheet.quality.solve_ms = MsSince(ts);
  if (sheet.period_u.isZero() && sheet.period_v.isZero()) {
    internal::MeasureQuality(dist, x, &sheet.quality);
  } else {
    MeasurePeriodicQuality(dist, PeriodsOf(surface, nu, nv, options_), x, sheet.period_u,
                           sheet.period_v, &sheet.quality);
  }
  if (sheet.quality.folded_cells > 0) {
    return Status(ErrorCode::kNotConverged,
                  std::to_string(sheet.quality.folded_cells) + " of " +
                      std::to_string((nu - 1) * (nv - 1)) +
                      " flat cells are folded (inverted or not convex), so the flat sheet "
                      "cannot be inverted; sample the surface more finely, use a larger "
                      "range, or split the surface where it bends sharply");
  }
  sheet.nu = nu;
  sheet.nv = nv;
  sheet.points = std::move(grid.points);
  sheet.normals = std::move(grid.normals);
  sheet.flat = std::move(x);
  sheet.quality.total_ms = MsSince(t0);
  return sheet;
}

Result<FlatSheet> FlattenSurface(const Surface& surface, const SamplingOptions& sampling,
                                 const FlattenOptions& options) {
  Flattener flattener(options);
  return flattener.Flatten(surface, sampling);
}

}  // namespace surfdeform
