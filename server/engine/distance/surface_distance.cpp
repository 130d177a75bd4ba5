// Over ~600 lines: the cold measurement, the blend between anchors' paths
// and the refollowing of an edit's paths share one lattice, one path
// relaxation (Gauss-Newton on the lattice's Taylor surrogate) and one
// per-thread state, which live here unexported; split, they would need an
// internal header carrying all of them.
#include "engine/distance/surface_distance.hpp"

#include "engine/common/elapsed.hpp"
#include "engine/common/parallel.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
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

// For a unit tangent at cosine c = cos(alpha) off the chord: alpha / sin(alpha),
// and x = sin(alpha)^2. Small angles (the common case) by the asin series
// (relative error 1e-7 at 0.3 rad), with no root; others by atan2.
double AngleOverSine(double c, double x) {
  if (x < 0.09 && c > 0.0) return 1.0 + x * (1.0 / 6.0 + x * (3.0 / 40.0 + x * (5.0 / 112.0)));
  const double s = std::sqrt(x);
  return s > 0.0 ? std::atan2(s, c) / s : 0.0;
}

// x / (2 sin(x / 2)) for x >= 0, given x^2 (series below 0.5 rad: error < 1e-13).
double ArcOverChord(double x2) {
  if (x2 < 0.25) return 1.0 + x2 * (1.0 / 24.0 + x2 * (7.0 / 5760.0 + x2 * (31.0 / 967680.0)));
  const double x = std::sqrt(x2);
  return 0.5 * x / std::sin(0.5 * x);
}

// Length of a smooth arc from p0 to p1 whose unit tangents at the ends are t0
// and t1. With theta(s) the tangent's angle off the chord (a vector normal to
// the chord: a at the start, e at the end), taken quadratic in s with the end
// values given and zero mean (the arc ends on the chord), the length is
// chord * (1 + <theta^2> / 2 + ...), and <theta^2> = (2 a.a + 2 e.e - a.e) / 15.
// The closed form phi / (2 sin(phi / 2)) with phi^2 = 12 <theta^2> carries the
// series on exactly for circular arcs (and so for helices and straight lines),
// and to O(h^4) for any smooth arc. a.a, e.e and a.e come from the tangents'
// cosines off the chord, so that the common case takes one root.
// `turn`, when given, receives phi: how far the arc turns.
double ArcLength(const Vec3& p0, const Vec3& p1, const Vec3& t0, const Vec3& t1,
                 double* turn = nullptr) {
  const Vec3 chord = p1 - p0;
  const double c = chord.norm();
  if (!(c > 0.0)) {
    if (turn != nullptr) *turn = 0.0;
    return 0.0;
  }
  const double inv = 1.0 / c;
  const double c0 = chord.dot(t0) * inv, c1 = chord.dot(t1) * inv;
  const double x0 = std::max(0.0, 1.0 - c0 * c0), x1 = std::max(0.0, 1.0 - c1 * c1);
  const double r0 = AngleOverSine(c0, x0), r1 = AngleOverSine(c1, x1);
  const double aa = r0 * r0 * x0, ee = r1 * r1 * x1;
  const double ae = r0 * r1 * (t0.dot(t1) - c0 * c1);  // the tangents' parts normal to the chord
  const double phi2 = std::max(0.0, 0.8 * (2.0 * (aa + ee) - ae));
  if (turn != nullptr) *turn = std::sqrt(phi2);
  return c * ArcOverChord(phi2);
}

// The points of a path: lattice_factor + 1, at most 17.
constexpr int kMaxPathPoints = 17;

// ArcLength of the `lanes` (1 to 4) arcs from p[l] to p[l + 1] with unit
// tangents t[l] and t[l + 1], into out[l]: four to an AVX2 vector where every
// arc takes ArcLength's common branch (a chord, small angles), else one by one.
void ArcLengths4(const Vec3* p, const Vec3* t, int lanes, double* out) {
  using Lanes = Eigen::Array4d;
  Lanes cx, cy, cz, ax, ay, az, bx, by, bz;
  for (int l = 0; l < 4; ++l) {
    const int k = std::min(l, lanes - 1);  // a short tail repeats its last arc
    const Vec3 chord = p[k + 1] - p[k];
    cx[l] = chord.x();
    cy[l] = chord.y();
    cz[l] = chord.z();
    ax[l] = t[k].x();
    ay[l] = t[k].y();
    az[l] = t[k].z();
    bx[l] = t[k + 1].x();
    by[l] = t[k + 1].y();
    bz[l] = t[k + 1].z();
  }
  const Lanes c = (cx * cx + cy * cy + cz * cz).sqrt();
  const Lanes inv = c.inverse();
  const Lanes c0 = (cx * ax + cy * ay + cz * az) * inv;
  const Lanes c1 = (cx * bx + cy * by + cz * bz) * inv;
  const Lanes x0 = (1.0 - c0 * c0).max(0.0), x1 = (1.0 - c1 * c1).max(0.0);
  auto angle_over_sine = [](const Lanes& x) {
    return 1.0 + x * (1.0 / 6.0 + x * (3.0 / 40.0 + x * (5.0 / 112.0)));
  };
  const Lanes r0 = angle_over_sine(x0), r1 = angle_over_sine(x1);
  const Lanes aa = r0 * r0 * x0, ee = r1 * r1 * x1;
  const Lanes ae = r0 * r1 * ((ax * bx + ay * by + az * bz) - c0 * c1);
  const Lanes phi2 = (0.8 * (2.0 * (aa + ee) - ae)).max(0.0);
  const bool common = (c > 0.0).all() && (x0 < 0.09).all() && (c0 > 0.0).all() &&
                      (x1 < 0.09).all() && (c1 > 0.0).all() && (phi2 < 0.25).all();
  if (!common) {
    for (int l = 0; l < lanes; ++l) out[l] = ArcLength(p[l], p[l + 1], t[l], t[l + 1]);
    return;
  }
  const Lanes arc =
      c * (1.0 + phi2 * (1.0 / 24.0 + phi2 * (7.0 / 5760.0 + phi2 * (31.0 / 967680.0))));
  for (int l = 0; l < lanes; ++l) out[l] = arc[l];
}

// Length of the smooth curve on the surface through the path points p[0..m]:
// between consecutive points an arc (ArcLength) whose end tangents lie in the
// tangent planes (normals n, of any length; zero: none), along the (central,
// or second-order one-sided at the ends) difference of the neighbouring
// points. For points on a geodesic this matches its length to O(h^4) per
// sub-segment, whatever the path's parameterisation.
double PathLength(const Vec3* p, const Vec3* n, int m) {
  auto tangent = [&](int k) {
    Vec3 t;
    if (m == 1) {
      t = p[1] - p[0];
    } else if (k == 0) {
      t = -3.0 * p[0] + 4.0 * p[1] - p[2];
    } else if (k == m) {
      t = 3.0 * p[m] - 4.0 * p[m - 1] + p[m - 2];
    } else {
      t = p[k + 1] - p[k - 1];
    }
    const double n2 = n[k].squaredNorm();
    if (n2 > 0.0) t -= n[k] * (n[k].dot(t) / n2);
    const double len = t.norm();
    return len > 0.0 ? Vec3(t * (1.0 / len)) : Vec3::Zero();
  };
  // The arcs four at a time (ArcLengths4), summed in order.
  Vec3 t[kMaxPathPoints];
  for (int k = 0; k <= m; ++k) t[k] = tangent(k);
  double len = 0.0;
  for (int k = 0; k < m; k += 4) {
    const int lanes = std::min(4, m - k);
    double arcs[4];
    ArcLengths4(p + k, t + k, lanes, arcs);
    for (int l = 0; l < lanes; ++l) len += arcs[l];
  }
  return len;
}

// Pairs whose chord turns by less than this (radians) are measured directly
// (DirectLength); measured on a cone, its error stays below 0.01 turn^4, so
// ~1e-8 relative here.
constexpr double kDirectMaxTurn = 0.03;
// Pairs whose chord turned by this much on every surface a remeasurement
// follows the paths of are measured along the path without a direct look.
constexpr double kClearTurn = 2.0 * kDirectMaxTurn;

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
// `c_scratch` and `d_scratch` are reused between calls (no allocation per pair).
double GaussNewtonStep(const std::vector<PathPoint>& path, std::vector<Vec2>* step,
                       std::vector<Eigen::Matrix2d>* c_scratch, std::vector<Vec2>* d_scratch) {
  const int m = static_cast<int>(path.size()) - 2;  // interior points 1..m
  step->assign(m, Vec2::Zero());
  if (m <= 0) return 0.0;
  // Block tridiagonal system: diag D_k = 4 J_k^T J_k, upper O_k = -2 J_k^T J_{k+1},
  // right-hand side -g_k = -2 J_k^T (2 P_k - P_{k-1} - P_{k+1}).
  c_scratch->resize(m);
  d_scratch->resize(m);
  std::vector<Eigen::Matrix2d>& c = *c_scratch;
  std::vector<Vec2>& d = *d_scratch;
  // The 3x2 products as dot products of the Jacobians' columns: Eigen's
  // generic small products here cost a quarter of a warm measurement.
  Eigen::Matrix2d prev_upper = Eigen::Matrix2d::Zero();
  for (int k = 0; k < m; ++k) {
    const PathPoint& a = path[k];
    const PathPoint& b = path[k + 1];
    const PathPoint& n = path[k + 2];
    const Vec3 bu = b.j.col(0), bv = b.j.col(1), nu = n.j.col(0), nv = n.j.col(1);
    const Vec3 w = 2.0 * b.p - a.p - n.p;
    const double uv = 4.0 * bu.dot(bv);
    Eigen::Matrix2d s;
    s << 4.0 * bu.squaredNorm(), uv, uv, 4.0 * bv.squaredNorm();
    Vec2 r(-2.0 * bu.dot(w), -2.0 * bv.dot(w));
    if (k > 0) {
      s.noalias() -= prev_upper.transpose() * c[k - 1];
      r.noalias() -= prev_upper.transpose() * d[k - 1];
    }
    Eigen::Matrix2d upper;
    upper << -2.0 * bu.dot(nu), -2.0 * bu.dot(nv), -2.0 * bv.dot(nu), -2.0 * bv.dot(nv);
    const double det = s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0);
    if (!(std::abs(det) > 0.0)) return 0.0;
    Eigen::Matrix2d inv;
    inv << s(1, 1), -s(0, 1), -s(1, 0), s(0, 0);
    inv *= 1.0 / det;
    c[k].noalias() = inv * upper;
    d[k].noalias() = inv * r;
    prev_upper = upper;
  }
  (*step)[m - 1] = d[m - 1];
  for (int k = m - 2; k >= 0; --k) (*step)[k] = d[k] - c[k] * (*step)[k + 1];
  double largest2 = 0.0;
  for (int k = 0; k < m; ++k) {
    const Vec2& t = (*step)[k];
    largest2 = std::max(
        largest2, (path[k + 1].j.col(0) * t.x() + path[k + 1].j.col(1) * t.y()).squaredNorm());
  }
  return std::sqrt(largest2);
}

// The surface and its derivatives on a lattice `f` times finer than the
// sample grid: the straight paths run through its points.
struct Lattice {
  int f = 0;
  int lu = 0;
  int lv = 0;
  double hu = 0.0;
  double hv = 0.0;
  std::vector<LatticePoint> points;

  const LatticePoint& At(int a, int b) const { return points[a + static_cast<size_t>(lu) * b]; }
  // Grid sample (i, j).
  const PathPoint& Sample(int i, int j) const { return At(f * i, f * j).first; }
};

// The path point at parameters q near lattice point `base`: by the
// second-order Taylor expansion there when q is within a quarter lattice step
// (error O(|q - q_l|^3), far below the distances' accuracy), else evaluated.
PathPoint MovedPathPoint(const Surface& surface, const Lattice& lattice, int base, const Vec2& q) {
  const LatticePoint& l = lattice.points[base];
  const Vec2 d = q - l.first.q;
  if (std::abs(d.x()) > 0.25 * lattice.hu || std::abs(d.y()) > 0.25 * lattice.hv) {
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

Lattice BuildLattice(const Surface& surface, int nu, int nv, int f, int threads) {
  Lattice l;
  l.f = f;
  l.lu = f * (nu - 1) + 1;
  l.lv = f * (nv - 1) + 1;
  l.hu = 1.0 / (l.lu - 1);
  l.hv = 1.0 / (l.lv - 1);
  l.points.resize(static_cast<size_t>(l.lu) * l.lv);
  // A row at a time through EvaluateMany (the bicubic patch: 4 points to a vector).
  ParallelChunks(l.lv, threads, [&](int, int b0, int b1) {
    std::vector<Vec2> q(l.lu);
    std::vector<SurfacePoint> s(l.lu);
    for (int b = b0; b < b1; ++b) {
      for (int a = 0; a < l.lu; ++a) q[a] = Vec2(a * l.hu, b * l.hv);
      surface.EvaluateMany(q, 2, s);
      for (int a = 0; a < l.lu; ++a) {
        const int index = a + l.lu * b;
        LatticePoint& p = l.points[index];
        p.first = MakePathPoint(s[a], q[a], index);
        p.suu = s[a].suu;
        p.suv = s[a].suv;
        p.svv = s[a].svv;
      }
    }
  });
  return l;
}

// Each chunk's own state, a cache line apart: the counters and the vectors'
// ends change at every pair, and two threads writing one line made two
// threads slower than one (measured: 4.1 against 3.5 ms, Figure 10 at 16x16).
struct alignas(64) ChunkState {
  int relaxed = 0;
  int direct = 0;
  int reused = 0;
  long long failed = -1;  // first failing edge index
  bool out_of_time = false;
  std::vector<PathPoint> path, trial;
  std::vector<Vec2> step;
  std::vector<Eigen::Matrix2d> c;  // GaussNewtonStep's
  std::vector<Vec2> d;
  std::vector<SurfacePoint> evaluated;
  std::vector<Vec2> blended;
  std::vector<Vec3> points, normals;  // a path's, for PathLength
  double turn = 0.0;                  // the last pair's chord turn (DirectLength)
};

// The length of a path from `start` to `finish` through the surface at
// parameters q (its interior points), each evaluated exactly: the length of
// the parameter path, as every measurement along a relaxed or reused path
// takes it.
double LengthThrough(const Surface& surface, const PathPoint& start, const PathPoint& finish,
                     std::span<const Vec2> q, ChunkState& state) {
  const size_t m = q.size();
  state.evaluated.resize(m);
  surface.EvaluateMany(q, 1, state.evaluated);
  state.points.resize(m + 2);
  state.normals.resize(m + 2);
  state.points[0] = start.p;
  state.normals[0] = start.n;
  for (size_t k = 0; k < m; ++k) {
    state.points[k + 1] = state.evaluated[k].p;
    state.normals[k + 1] = state.evaluated[k].su.cross(state.evaluated[k].sv);
  }
  state.points[m + 1] = finish.p;
  state.normals[m + 1] = finish.n;
  return PathLength(state.points.data(), state.normals.data(), static_cast<int>(m + 1));
}

// Whether the pair's chord turns little enough to be measured directly
// (DirectLength); if so, its distance goes to *d and it is counted.
bool MeasuredDirectly(const PathPoint& start, const PathPoint& finish, ChunkState& state,
                      double* d) {
  double turn = 0.0;
  *d = DirectLength(start, finish, &turn);
  state.turn = turn;
  if (!(turn < kDirectMaxTurn)) return false;
  ++state.direct;
  return true;
}

// Measures the pair from sample (i, j) to (i + di, j + dj) as described in
// the header: directly where the chord turns little, else along a path from
// the straight segment, relaxed. The chord's turn goes to state.turn; when a
// path is followed, the parameters of its f - 1 interior points go to
// `record` (if given).
double MeasurePair(const Surface& surface, const Lattice& lattice, int i, int j, int di, int dj,
                   int relax_steps, ChunkState& state, Vec2* record) {
  const int f = lattice.f;
  const PathPoint& start = lattice.Sample(i, j);
  const PathPoint& finish = lattice.Sample(i + di, j + dj);
  double direct = 0.0;
  if (MeasuredDirectly(start, finish, state, &direct)) return direct;
  // A path of f sub-segments of (di, dj) / f cells: each ends on a lattice point.
  std::vector<PathPoint>& path = state.path;
  path.clear();
  for (int k = 0; k <= f; ++k) path.push_back(lattice.At(f * i + k * di, f * j + k * dj).first);
  bool was_relaxed = false;
  double energy = PathEnergy(path);
  for (int it = 0; it < relax_steps; ++it) {
    const double moved = GaussNewtonStep(path, &state.step, &state.c, &state.d);
    const double scale = std::sqrt(energy * f);  // ~ the path length
    // A move below 1e-7 of the length changes the length by ~1e-14 of it:
    // the path is a geodesic already. After a first step, Gauss-Newton's
    // next step is second order: worth it only after a large first one.
    if (!(moved > (it == 0 ? 1e-7 : 1e-4) * scale)) break;
    if (!(moved < 0.5 * scale)) break;  // not a local correction: keep the path
    state.trial = path;
    for (size_t k = 0; k < state.step.size(); ++k) {
      const PathPoint& from = path[k + 1];
      state.trial[k + 1] = MovedPathPoint(surface, lattice, from.base, from.q + state.step[k]);
    }
    const double trial_energy = PathEnergy(state.trial);
    if (!(trial_energy < energy)) break;  // also rejects NaN
    path.swap(state.trial);
    energy = trial_energy;
    was_relaxed = true;
  }
  state.relaxed += was_relaxed ? 1 : 0;
  if (record != nullptr) {
    for (int k = 1; k < f; ++k) record[k - 1] = path[k].q;
  }
  if (was_relaxed) {
    // The relaxed points where the surface is: the Taylor surrogate that
    // placed them is off by ~1e-6 of the length in places, and the length is
    // then that of the parameter path, as RemeasureSurfaceDistances measures.
    state.blended.resize(f - 1);
    for (int k = 1; k < f; ++k) state.blended[k - 1] = path[k].q;
    return LengthThrough(surface, start, finish, state.blended, state);
  }
  state.points.resize(f + 1);
  state.normals.resize(f + 1);
  for (int k = 0; k <= f; ++k) {
    state.points[k] = path[k].p;
    state.normals[k] = path[k].n;
  }
  return PathLength(state.points.data(), state.normals.data(), f);
}

// RefollowPair measures a moved path again only when it moved by more than
// this fraction of its length.
constexpr double kRemeasuredMove = 1e-4;

// Measures the pair from sample (i, j) to (i + di, j + dj) starting from the
// path `q` (its interior points' parameters) that the measurement of an
// earlier version of the surface followed (RefollowSurfaceDistances): directly
// where the chord now turns little, else along that path evaluated exactly and
// along the path moved by one Gauss-Newton step from those evaluations, the
// shorter. The chord's turn goes to state.turn; the path measured goes to
// `record` (if given) when a path is followed.
double RefollowPair(const Surface& surface, const Lattice& lattice, int i, int j, int di, int dj,
                    std::span<const Vec2> q, ChunkState& state, Vec2* record) {
  const PathPoint& start = lattice.Sample(i, j);
  const PathPoint& finish = lattice.Sample(i + di, j + dj);
  double direct = 0.0;
  if (MeasuredDirectly(start, finish, state, &direct)) return direct;
  ++state.reused;
  const size_t m = q.size();
  const double before = LengthThrough(surface, start, finish, q, state);
  // Its points with the first derivatives just evaluated: a Gauss-Newton
  // step's (which needs no normals).
  std::vector<PathPoint>& path = state.path;
  path.resize(m + 2);
  path[0] = start;
  path[m + 1] = finish;
  for (size_t k = 0; k < m; ++k) {
    path[k + 1].p = state.evaluated[k].p;
    path[k + 1].j.col(0) = state.evaluated[k].su;
    path[k + 1].j.col(1) = state.evaluated[k].sv;
  }
  auto keep = [&](std::span<const Vec2> kept) {
    if (record != nullptr) std::copy(kept.begin(), kept.end(), record);
  };
  const double moved = GaussNewtonStep(path, &state.step, &state.c, &state.d);
  // As MeasurePair: a move below 1e-7 of the length is no move, and one of
  // half the length is not a local correction.
  if (!(moved > 1e-7 * before) || !(moved < 0.5 * before)) {
    keep(q);
    return before;
  }
  state.blended.resize(m);
  for (size_t k = 0; k < m; ++k) state.blended[k] = q[k] + state.step[k];
  // A path's length changes at second order in a move of it: below
  // kRemeasuredMove of the length, the moved path is at most ~1e-8 of it
  // shorter (measured: the stress stays within the solver's tolerance of a
  // cold measurement's). It is kept for the next edit, unmeasured.
  if (moved < kRemeasuredMove * before) {
    keep(state.blended);
    return before;
  }
  const double after = LengthThrough(surface, start, finish, state.blended, state);
  if (!(after < before)) {  // also rejects NaN
    keep(q);
    return before;
  }
  ++state.relaxed;
  keep(state.blended);
  return after;
}

// Work items are (offset, row) with a fixed place in the edge list, so the
// result is the same for any thread count. Half of the offsets: each
// unordered pair once.
struct Row {
  int di, dj, j;
  size_t first;  // index of its first edge
};

std::vector<Row> PairRows(int nu, int nv, int r, size_t* total) {
  std::vector<Row> rows;
  *total = 0;
  for (int dj = 0; dj <= r; ++dj) {
    for (int di = -r; di <= r; ++di) {
      if (dj == 0 && di <= 0) continue;
      const int per_row = std::max(0, nu - std::abs(di));
      for (int j = 0; j + dj < nv; ++j) {
        rows.push_back({di, dj, j, *total});
        *total += per_row;
      }
    }
  }
  return rows;
}

// Every pair within range, measured by `measure(i, j, di, dj, edge, state)`
// on `threads` threads, with the cell areas, the counts, the deadline and the
// failures that both measurements share.
template <typename Measure>
Result<SurfaceDistances> MeasureAllPairs(int nu, int nv, int threads, const Lattice& lattice,
                                         const DistanceOptions& options, const Measure& measure) {
  const int r = options.range;
  const Deadline deadline = DeadlineAfter(options.started, options.time_budget_ms, options.cancel);
  SurfaceDistances out;
  out.nu = nu;
  out.nv = nv;
  out.range = r;
  size_t total = 0;
  const std::vector<Row> rows = PairRows(nu, nv, r, &total);
  out.edges.resize(total);
  std::vector<ChunkState> chunks(threads);
  // Rows are dealt round-robin: the offsets come in order of length, and
  // longer ones bend more often (relaxed paths), so contiguous chunks left
  // one thread with most of the work.
  const int row_count = static_cast<int>(rows.size());
  ParallelChunks(threads, threads, [&](int slot, int, int) {
    ChunkState& state = chunks[slot];
    for (int ri = slot; ri < row_count; ri += threads) {
      if (deadline.Passed()) {
        state.out_of_time = true;
        break;
      }
      const auto [di, dj, j, first] = rows[ri];
      const int ring = std::max(std::abs(di), dj);
      size_t slot_edge = first;
      for (int i = std::max(0, -di); i < nu && i + di < nu; ++i, ++slot_edge) {
        GridEdge& e = out.edges[slot_edge];
        e.i = i + nu * j;  // dj > 0, or dj == 0 and di > 0: so i < j
        e.j = (i + di) + nu * (j + dj);
        e.di = di;
        e.dj = dj;
        e.ring = ring;
        e.d = measure(i, j, di, dj, slot_edge, state);
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
    out.reused_paths += c.reused;
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
  const int f = lattice.f;
  out.cell_areas.assign(static_cast<size_t>(nu - 1) * (nv - 1), 0.0);
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i + 1 < nu; ++i) {
      double area = 0.0;
      for (int b = 0; b <= f; ++b) {
        for (int a = 0; a <= f; ++a) {
          const PathPoint& pp = lattice.At(f * i + a, f * j + b).first;
          const double w = (a == 0 || a == f ? 0.5 : 1.0) * (b == 0 || b == f ? 0.5 : 1.0);
          area += w * pp.j.col(0).cross(pp.j.col(1)).norm();
        }
      }
      out.cell_areas[i + (nu - 1) * j] = area * lattice.hu * lattice.hv;
    }
  }
  return out;
}

// The checks and settings both measurements share.
Status CheckGrid(int nu, int nv, const DistanceOptions& options) {
  if (options.range < 1 || options.range > 8) {
    return InvalidArgument("must be from 1 to 8, got " + std::to_string(options.range), "range");
  }
  if (nu < 2 || nv < 2) return InvalidArgument("the grid needs at least 2 x 2 samples");
  return Status::Ok();
}

int LatticeFactor(int nu, int nv, const DistanceOptions& options) {
  return DistanceLatticeFactor(nu, nv, options.lattice_factor);
}

// Small grids are not worth a thread.
int DistanceThreads(int nu, int nv, const DistanceOptions& options) {
  return nu * nv < 64 ? 1 : ResolveThreads(options.threads);
}

// Empty paths for every pair of an nu x nv grid within `range`, lattice `f`.
void StartPaths(int nu, int nv, int range, int f, DistancePaths* paths) {
  size_t total = 0;
  PairRows(nu, nv, range, &total);
  *paths = DistancePaths{};
  paths->nu = nu;
  paths->nv = nv;
  paths->range = range;
  paths->lattice_factor = f;
  paths->turn.assign(total, 0.0);
  paths->q.resize(total * (f - 1));
}

}  // namespace

int DistanceLatticeFactor(int nu, int nv, int given) {
  if (given > 0) return given;
  return std::max(nu, nv) <= 64 ? 4 : 2;
}

size_t DistanceLatticePoints(int nu, int nv, int given) {
  const size_t f = static_cast<size_t>(DistanceLatticeFactor(nu, nv, given));
  return (f * static_cast<size_t>(nu - 1) + 1) * (f * static_cast<size_t>(nv - 1) + 1);
}

bool DistancePaths::Followed(size_t edge) const { return !(turn[edge] < kDirectMaxTurn); }

Result<SurfaceDistances> ComputeSurfaceDistances(const Surface& surface, int nu, int nv,
                                                 const DistanceOptions& options,
                                                 DistancePaths* paths) {
  SURFDEFORM_RETURN_IF_ERROR(CheckGrid(nu, nv, options));
  const int f = LatticeFactor(nu, nv, options);
  const int threads = DistanceThreads(nu, nv, options);
  const Lattice lattice = BuildLattice(surface, nu, nv, f, threads);
  if (paths != nullptr) StartPaths(nu, nv, options.range, f, paths);
  auto measure = [&](int i, int j, int di, int dj, size_t edge, ChunkState& state) {
    Vec2* record = paths != nullptr ? paths->q.data() + edge * (f - 1) : nullptr;
    const double d =
        MeasurePair(surface, lattice, i, j, di, dj, options.relax_steps, state, record);
    if (paths != nullptr) paths->turn[edge] = state.turn;
    return d;
  };
  return MeasureAllPairs(nu, nv, threads, lattice, options, measure);
}

Result<SurfaceDistances> RemeasureSurfaceDistances(const Surface& surface,
                                                   std::span<const PathBlend> blends,
                                                   const DistanceOptions& options) {
  if (blends.empty() || blends[0].empty()) return InvalidArgument("no paths to measure along");
  const int nu = blends[0][0].paths->nu, nv = blends[0][0].paths->nv;
  SURFDEFORM_RETURN_IF_ERROR(CheckGrid(nu, nv, options));
  for (const PathBlend& blend : blends) {
    double weights = 0.0;
    for (const WeightedPaths& w : blend) {
      const DistancePaths& p = *w.paths;
      if (p.nu != nu || p.nv != nv || options.range != p.range ||
          LatticeFactor(nu, nv, options) != p.lattice_factor) {
        return InvalidArgument("the paths were followed on another grid, range or lattice");
      }
      if (!std::isfinite(w.weight)) return InvalidArgument("the paths' weights must be finite");
      weights += w.weight;
    }
    if (!(std::abs(weights - 1.0) < 1e-12)) {
      return InvalidArgument("the paths' weights must add up to 1");
    }
  }
  const int f = blends[0][0].paths->lattice_factor;
  const int threads = DistanceThreads(nu, nv, options);
  const Lattice lattice = BuildLattice(surface, nu, nv, f, threads);
  auto measure = [&](int i, int j, int di, int dj, size_t edge, ChunkState& state) {
    const PathBlend* blend = nullptr;  // the first whose paths all followed this pair
    for (const PathBlend& b : blends) {
      bool all = true;
      for (const WeightedPaths& w : b) all = all && w.paths->Followed(edge);
      if (all) {
        blend = &b;
        break;
      }
    }
    if (blend == nullptr) {
      return MeasurePair(surface, lattice, i, j, di, dj, options.relax_steps, state, nullptr);
    }
    const PathPoint& start = lattice.Sample(i, j);
    const PathPoint& finish = lattice.Sample(i + di, j + dj);
    // Where every path's chord turned by twice the direct measurement's
    // limit, this one does not come under it: no need to look.
    bool turned = true;
    for (const WeightedPaths& w : *blend) turned = turned && w.paths->turn[edge] >= kClearTurn;
    double direct = 0.0;
    if (!turned && MeasuredDirectly(start, finish, state, &direct)) return direct;
    const size_t m = static_cast<size_t>(f - 1);
    state.blended.resize(m);
    for (size_t k = 0; k < m; ++k) {
      Vec2 q = Vec2::Zero();
      for (const WeightedPaths& w : *blend) q += w.weight * w.paths->q[edge * m + k];
      state.blended[k] = q;
    }
    ++state.reused;
    return LengthThrough(surface, start, finish, state.blended, state);
  };
  return MeasureAllPairs(nu, nv, threads, lattice, options, measure);
}

Result<SurfaceDistances> RefollowSurfaceDistances(const Surface& surface,
                                                  const DistancePaths& previous,
                                                  const DistanceOptions& options,
                                                  DistancePaths* next) {
  const int nu = previous.nu, nv = previous.nv;
  SURFDEFORM_RETURN_IF_ERROR(CheckGrid(nu, nv, options));
  const int f = LatticeFactor(nu, nv, options);
  size_t total = 0;
  PairRows(nu, nv, options.range, &total);
  if (options.range != previous.range || f != previous.lattice_factor ||
      previous.turn.size() != total || previous.q.size() != total * (f - 1)) {
    return InvalidArgument("the paths were followed on another grid, range or lattice");
  }
  const int threads = DistanceThreads(nu, nv, options);
  const Lattice lattice = BuildLattice(surface, nu, nv, f, threads);
  if (next != nullptr) StartPaths(nu, nv, options.range, f, next);
  const size_t m = static_cast<size_t>(f - 1);
  auto measure = [&](int i, int j, int di, int dj, size_t edge, ChunkState& state) {
    Vec2* record = next != nullptr ? next->q.data() + edge * m : nullptr;
    const double d =
        previous.Followed(edge)
            ? RefollowPair(surface, lattice, i, j, di, dj,
                           std::span<const Vec2>(previous.q.data() + edge * m, m), state, record)
            : MeasurePair(surface, lattice, i, j, di, dj, options.relax_steps, state, record);
    if (next != nullptr) next->turn[edge] = state.turn;
    return d;
  };
  return MeasureAllPairs(nu, nv, threads, lattice, options, measure);
}

}  // namespace surfdeform
