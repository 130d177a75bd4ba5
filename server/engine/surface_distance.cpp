#include "engine/surface_distance.hpp"

#include "engine/elapsed.hpp"
#include "engine/parallel.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace surfdeform {
namespace {

using Mat32 = Eigen::Matrix<double, 3, 2>;

struct PathPoint {
  Vec2 q;         // parameters
  Vec3 p;         // position
  Mat32 j;        // [Su Sv]
  Vec3 n;         // unit normal
  int base = -1;  // the lattice point it started from
};

// A lattice point: the surface and its derivatives up to second order.
struct LatticePoint {
  PathPoint first;  // position, first derivatives, normal
  Vec3 suu, suv, svv;
};

PathPoint MakePathPoint(const SurfacePoint& s, const Vec2& q, int base) {
  PathPoint pp;
  pp.q = q;
  pp.p = s.p;
  pp.j.col(0) = s.su;
  pp.j.col(1) = s.sv;
  pp.n = UnitNormal(s);
  pp.base = base;
  return pp;
}

// The path point at parameters q near lattice point `l`: by the second-order
// Taylor expansion there when q is within a quarter lattice step (error
// O(|q - q_l|^3), far below the distances' accuracy), else evaluated.
PathPoint MovedPathPoint(const Surface& surface, const LatticePoint& l, int base, const Vec2& q,
                         double hu, double hv) {
  const Vec2 d = q - l.first.q;
  if (std::abs(d.x()) > 0.25 * hu || std::abs(d.y()) > 0.25 * hv) {
    return MakePathPoint(surface.Evaluate(q.x(), q.y(), 1), q, base);
  }
  SurfacePoint s;
  const Vec3 su = l.first.j.col(0), sv = l.first.j.col(1);
  s.su = su + l.suu * d.x() + l.suv * d.y();
  s.sv = sv + l.suv * d.x() + l.svv * d.y();
  s.p = l.first.p + su * d.x() + sv * d.y() +
        0.5 * (l.suu * (d.x() * d.x()) + 2.0 * l.suv * (d.x() * d.y()) + l.svv * (d.y() * d.y()));
  return MakePathPoint(s, q, base);
}

// atan2(s, c) for s >= 0, s^2 + c^2 = 1: the asin series for the small angles
// met here, exact enough (relative 1e-7 at 0.3 rad) and much cheaper.
double AngleFromSinCos(double s, double c) {
  if (s < 0.3 && c > 0.0) {
    const double s2 = s * s;
    return s * (1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0 + s2 * (5.0 / 112.0))));
  }
  return std::atan2(s, c);
}

// x / (2 sin(x / 2)) for x >= 0 (series below 0.5 rad: error < 1e-13).
double ArcOverChord(double x) {
  if (x < 0.5) {
    const double x2 = x * x;
    return 1.0 + x2 * (1.0 / 24.0 + x2 * (7.0 / 5760.0 + x2 * (31.0 / 967680.0)));
  }
  return 0.5 * x / std::sin(0.5 * x);
}

// Length of a smooth arc from p0 to p1 whose unit tangents at the ends are t0
// and t1. With theta(s) the tangent's angle off the chord (a vector normal to
// the chord), taken quadratic in s with the end values given and zero mean (the
// arc ends on the chord), the length is chord * (1 + <theta^2> / 2 + ...). The
// closed form phi / (2 sin(phi / 2)) with phi^2 = 12 <theta^2> carries the
// series on exactly for circular arcs (and so for helices and straight lines),
// and to O(h^4) for any smooth arc.
// `turn`, when given, receives phi: how far the arc turns.
double ArcLength(const Vec3& p0, const Vec3& p1, const Vec3& t0, const Vec3& t1,
                 double* turn = nullptr) {
  const Vec3 chord = p1 - p0;
  const double c = chord.norm();
  if (!(c > 0.0)) {
    if (turn != nullptr) *turn = 0.0;
    return 0.0;
  }
  const Vec3 dir = chord / c;
  auto angle_vector = [&](const Vec3& t) {
    const Vec3 perp = t - dir * dir.dot(t);
    const double s = perp.norm();
    if (!(s > 0.0)) return Vec3(Vec3::Zero());
    return Vec3(perp * (AngleFromSinCos(s, dir.dot(t)) / s));
  };
  const Vec3 a = angle_vector(t0);
  const Vec3 e = angle_vector(t1);
  const Vec3 q = 3.0 * (a + e);  // theta(s) = a + b s + q s^2
  const Vec3 b = -2.0 * e - 4.0 * a;
  const double mean_sq = a.squaredNorm() + a.dot(b) + (b.squaredNorm() + 2.0 * a.dot(q)) / 3.0 +
                         b.dot(q) / 2.0 + q.squaredNorm() / 5.0;
  const double phi = std::sqrt(std::max(0.0, 12.0 * mean_sq));
  if (turn != nullptr) *turn = phi;
  return c * ArcOverChord(phi);
}

// Length of the smooth curve on the surface through the path points: between
// consecutive points an arc (ArcLength) whose end tangents lie in the tangent
// planes, along the (central, or second-order one-sided at the ends) difference
// of the neighbouring points. For points on a geodesic this matches its length
// to O(h^4) per sub-segment, whatever the path's parameterisation.
double PathLength(const std::vector<PathPoint>& path) {
  const int m = static_cast<int>(path.size()) - 1;
  auto tangent = [&](int k) {
    Vec3 t;
    if (m == 1) {
      t = path[1].p - path[0].p;
    } else if (k == 0) {
      t = -3.0 * path[0].p + 4.0 * path[1].p - path[2].p;
    } else if (k == m) {
      t = 3.0 * path[m].p - 4.0 * path[m - 1].p + path[m - 2].p;
    } else {
      t = path[k + 1].p - path[k - 1].p;
    }
    const Vec3& n = path[k].n;
    t -= n * n.dot(t);
    const double len = t.norm();
    return len > 0.0 ? Vec3(t / len) : Vec3::Zero();
  };
  double len = 0.0;
  Vec3 t0 = tangent(0);
  for (int k = 0; k < m; ++k) {
    const Vec3 t1 = tangent(k + 1);
    len += ArcLength(path[k].p, path[k + 1].p, t0, t1);
    t0 = t1;
  }
  return len;
}

// Pairs whose chord turns by less than this (radians) are measured directly
// (DirectLength); measured on a cone, its error stays below 0.01 turn^4, so
// ~1e-8 relative here.
constexpr double kDirectMaxTurn = 0.03;

// The length of the normal section through a and b (the surface's
// intersection with the plane through the chord and the normal at a, nearly
// the geodesic: the two differ at fifth order in the length) from the chord
// and its projections on the tangent planes at both ends. Fills the turn.
double DirectLength(const PathPoint& a, const PathPoint& b, double* turn) {
  const Vec3 chord = b.p - a.p;
  Vec3 t0 = chord - a.n * a.n.dot(chord);
  Vec3 t1 = chord - b.n * b.n.dot(chord);
  const double l0 = t0.norm(), l1 = t1.norm();
  if (!(l0 > 0.0) || !(l1 > 0.0)) {
    *turn = std::numeric_limits<double>::infinity();
    return 0.0;
  }
  return ArcLength(a.p, b.p, t0 / l0, t1 / l1, turn);
}

// The discrete path energy sum_k |P_{k+1} - P_k|^2 that the relaxation lowers.
double PathEnergy(const std::vector<PathPoint>& path) {
  double e = 0.0;
  for (size_t k = 0; k + 1 < path.size(); ++k) e += (path[k + 1].p - path[k].p).squaredNorm();
  return e;
}

// One Gauss-Newton step on E = sum_k |P_{k+1} - P_k|^2 over the interior points
// (the ends stay fixed). Writes the parameter updates to `step` and returns the
// largest resulting 3D displacement (first order).
double GaussNewtonStep(const std::vector<PathPoint>& path, std::vector<Vec2>* step) {
  const int m = static_cast<int>(path.size()) - 2;  // interior points 1..m
  step->assign(m, Vec2::Zero());
  if (m <= 0) return 0.0;
  // Block tridiagonal system: diag D_k = 4 J_k^T J_k, upper O_k = -2 J_k^T J_{k+1},
  // right-hand side -g_k = -2 J_k^T (2 P_k - P_{k-1} - P_{k+1}).
  std::vector<Eigen::Matrix2d> c(m);
  std::vector<Vec2> d(m);
  Eigen::Matrix2d prev_upper = Eigen::Matrix2d::Zero();
  for (int k = 0; k < m; ++k) {
    const PathPoint& a = path[k];
    const PathPoint& b = path[k + 1];
    const PathPoint& n = path[k + 2];
    const Eigen::Matrix2d diag = 4.0 * b.j.transpose() * b.j;
    const Vec2 rhs = -2.0 * b.j.transpose() * (2.0 * b.p - a.p - n.p);
    Eigen::Matrix2d s = diag;
    Vec2 r = rhs;
    if (k > 0) {
      s -= prev_upper.transpose() * c[k - 1];
      r -= prev_upper.transpose() * d[k - 1];
    }
    const Eigen::Matrix2d upper = -2.0 * b.j.transpose() * n.j;
    const double det = s.determinant();
    if (!(std::abs(det) > 0.0)) return 0.0;
    const Eigen::Matrix2d inv = s.inverse();
    c[k] = inv * upper;
    d[k] = inv * r;
    prev_upper = upper;
  }
  (*step)[m - 1] = d[m - 1];
  for (int k = m - 2; k >= 0; --k) (*step)[k] = d[k] - c[k] * (*step)[k + 1];
  double largest = 0.0;
  for (int k = 0; k < m; ++k) largest = std::max(largest, (path[k + 1].j * (*step)[k]).norm());
  return largest;
}

}  // namespace

Result<SurfaceDistances> ComputeSurfaceDistances(const Surface& surface, int nu, int nv,
                                                 const DistanceOptions& options) {
  if (options.range < 1 || options.range > 8) {
    return InvalidArgument("must be from 1 to 8, got " + std::to_string(options.range), "range");
  }
  if (nu < 2 || nv < 2) return InvalidArgument("the grid needs at least 2 x 2 samples");
  const int r = options.range;
  const auto deadline = DeadlineAfter(options.started, options.time_budget_ms);
  int f = options.lattice_factor;
  if (f <= 0) f = std::max(nu, nv) <= 64 ? 4 : 2;
  // Small grids are not worth a thread.
  const int threads = nu * nv < 64 ? 1 : ResolveThreads(options.threads);
  const int lu = f * (nu - 1) + 1;
  const int lv = f * (nv - 1) + 1;
  const double hu = 1.0 / (lu - 1);
  const double hv = 1.0 / (lv - 1);

  std::vector<LatticePoint> lattice(static_cast<size_t>(lu) * lv);
  ParallelChunks(lv, threads, [&](int, int b0, int b1) {
    for (int b = b0; b < b1; ++b) {
      for (int a = 0; a < lu; ++a) {
        const int index = a + lu * b;
        const SurfacePoint s = surface.Evaluate(a * hu, b * hv, 2);
        LatticePoint& l = lattice[index];
        l.first = MakePathPoint(s, Vec2(a * hu, b * hv), index);
        l.suu = s.suu;
        l.suv = s.suv;
        l.svv = s.svv;
      }
    }
  });

  SurfaceDistances out;
  out.nu = nu;
  out.nv = nv;
  out.range = r;
  // Half of the offsets: each unordered pair once. Work items are (offset, row)
  // with a fixed place in the edge list, so the result is the same for any
  // thread count.
  struct Row {
    int di, dj, j;
    size_t first;  // index of its first edge
  };
  std::vector<Row> rows;
  size_t total = 0;
  for (int dj = 0; dj <= r; ++dj) {
    for (int di = -r; di <= r; ++di) {
      if (dj == 0 && di <= 0) continue;
      const int per_row = std::max(0, nu - std::abs(di));
      for (int j = 0; j + dj < nv; ++j) {
        rows.push_back({di, dj, j, total});
        total += per_row;
      }
    }
  }
  out.edges.resize(total);
  // Each chunk's own state, a cache line apart: the counters and the
  // vectors' ends change at every pair, and two threads writing one line
  // made two threads slower than one (measured: 4.1 against 3.5 ms, Figure
  // 10 at 16x16).
  struct alignas(64) ChunkState {
    int relaxed = 0;
    int direct = 0;
    long long failed = -1;  // first failing edge index
    bool out_of_time = false;
    std::vector<PathPoint> path, trial;
    std::vector<Vec2> step;
  };
  std::vector<ChunkState> chunks(threads);
  // Rows are dealt round-robin: the offsets come in order of length, and
  // longer ones bend more often (relaxed paths), so contiguous chunks left
  // one thread with most of the work.
  const int row_count = static_cast<int>(rows.size());
  ParallelChunks(threads, threads, [&](int slot, int, int) {
    ChunkState& state = chunks[slot];
    std::vector<PathPoint>& path = state.path;
    std::vector<Vec2>& step = state.step;
    std::vector<PathPoint>& trial = state.trial;
    for (int ri = slot; ri < row_count; ri += threads) {
      if (std::chrono::steady_clock::now() > deadline) {
        state.out_of_time = true;
        break;
      }
      const auto [di, dj, j, first] = rows[ri];
      const int ring = std::max(std::abs(di), dj);
      size_t slot_edge = first;
      for (int i = std::max(0, -di); i < nu && i + di < nu; ++i, ++slot_edge) {
        const PathPoint& start = lattice[f * i + static_cast<size_t>(lu) * (f * j)].first;
        const PathPoint& finish =
            lattice[f * (i + di) + static_cast<size_t>(lu) * (f * (j + dj))].first;
        double turn = 0.0;
        const double direct = DirectLength(start, finish, &turn);
        GridEdge& e = out.edges[slot_edge];
        e.i = i + nu * j;  // dj > 0, or dj == 0 and di > 0: so i < j
        e.j = (i + di) + nu * (j + dj);
        e.di = di;
        e.dj = dj;
        e.ring = ring;
        if (turn < kDirectMaxTurn) {
          e.d = direct;
          ++state.direct;
          if (!std::isfinite(e.d) || !(e.d > 0.0)) {
            if (state.failed < 0) state.failed = static_cast<long long>(slot_edge);
          }
          continue;
        }
        // A path of f sub-segments of (di, dj) / f cells: each ends on a lattice point.
        path.clear();
        for (int k = 0; k <= f; ++k) {
          path.push_back(
              lattice[(f * i + k * di) + static_cast<size_t>(lu) * (f * j + k * dj)].first);
        }
        bool was_relaxed = false;
        double energy = PathEnergy(path);
        for (int it = 0; it < options.relax_steps; ++it) {
          const double moved = GaussNewtonStep(path, &step);
          const double scale = std::sqrt(energy * f);  // ~ the path length
          // A move below 1e-7 of the length changes the length by ~1e-14 of it:
          // the path is a geodesic already. After a first step, Gauss-Newton's
          // next step is second order: worth it only after a large first one.
          if (!(moved > (it == 0 ? 1e-7 : 1e-4) * scale)) break;
          if (!(moved < 0.5 * scale)) break;  // not a local correction: keep the path
          trial = path;
          for (size_t k = 0; k < step.size(); ++k) {
            const PathPoint& from = path[k + 1];
            trial[k + 1] =
                MovedPathPoint(surface, lattice[from.base], from.base, from.q + step[k], hu, hv);
          }
          const double trial_energy = PathEnergy(trial);
          if (!(trial_energy < energy)) break;  // also rejects NaN
          path.swap(trial);
          energy = trial_energy;
          was_relaxed = true;
        }
        const double length = PathLength(path);
        state.relaxed += was_relaxed ? 1 : 0;
        e.d = length;
        if ((!std::isfinite(e.d) || !(e.d > 0.0)) && state.failed < 0) {
          state.failed = static_cast<long long>(slot_edge);
        }
      }
    }
  });
  bool late = false;
  long long first_failure = -1;
  for (const ChunkState& c : chunks) {
    out.relaxed_paths += c.relaxed;
    out.direct_pairs += c.direct;
    late = late || c.out_of_time;
    if (c.failed >= 0 && (first_failure < 0 || c.failed < first_failure)) first_failure = c.failed;
  }
  if (late) {
    return Status::DeadlineExceeded(
        "the surface distances were not measured within the time budget of " +
            std::to_string(static_cast<long long>(options.time_budget_ms)) +
            " ms; use a coarser grid or a smaller range",
        "flatten", options.time_budget_ms, MsSince(options.started));
  }
  if (first_failure >= 0) {
    const GridEdge& e = out.edges[first_failure];
    return Degenerate("samples " + std::to_string(e.i) + " and " + std::to_string(e.j) +
                          " coincide on the surface (distance " + std::to_string(e.d) +
                          "): the surface is degenerate there",
                      "surface");
  }
  out.cell_areas.assign(static_cast<size_t>(nu - 1) * (nv - 1), 0.0);
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i + 1 < nu; ++i) {
      double area = 0.0;
      for (int b = 0; b <= f; ++b) {
        for (int a = 0; a <= f; ++a) {
          const PathPoint& pp = lattice[(f * i + a) + static_cast<size_t>(lu) * (f * j + b)].first;
          const double w = (a == 0 || a == f ? 0.5 : 1.0) * (b == 0 || b == f ? 0.5 : 1.0);
          area += w * pp.j.col(0).cross(pp.j.col(1)).norm();
        }
      }
      out.cell_areas[i + (nu - 1) * j] = area * hu * hv;
    }
  }
  return out;
}

}  // namespace surfdeform
