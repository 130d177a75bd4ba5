#include "engine/placement/placement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "base/format.hpp"
#include "engine/common/clamped_floor.hpp"
#include "engine/surface/surface_spec.hpp"

namespace surfdeform {
namespace {

using Mat3 = Eigen::Matrix3d;

// Rows: the model directions that become a, b (in-plane) and h (height);
// right-handed, so footprints are not mirrored.
Mat3 AxisBasis(UpAxis up) {
  Mat3 m;
  switch (up) {
    case UpAxis::kPosZ:
      m << 1, 0, 0, 0, 1, 0, 0, 0, 1;
      break;
    case UpAxis::kNegZ:
      m << 1, 0, 0, 0, -1, 0, 0, 0, -1;
      break;
    case UpAxis::kPosX:
      m << 0, 1, 0, 0, 0, 1, 1, 0, 0;
      break;
    case UpAxis::kNegX:
      m << 0, 1, 0, 0, 0, -1, -1, 0, 0;
      break;
    case UpAxis::kPosY:
      m << 0, 0, 1, 1, 0, 0, 0, 1, 0;
      break;
    case UpAxis::kNegY:
      m << 0, 0, 1, -1, 0, 0, 0, -1, 0;
      break;
    case UpAxis::kAuto:  // resolved before (ResolveUpAxis)
      m.setIdentity();
      break;
  }
  return m;
}

// The points that are not strictly inside the convex polygon of the points
// extreme in `k` directions spread evenly over the circle: those inside cannot
// be on the convex hull (Akl-Toussaint's heuristic, with k directions instead
// of four). Branch-free inner loops over the directions, which the compiler
// vectorises.
template <int k>
std::vector<Vec2> DropInterior(const std::vector<Vec2>& points) {
  if (points.size() < 3) return points;
  double dx[k], dy[k], best[k];
  size_t at[k];
  for (int d = 0; d < k; ++d) {
    const double angle = 2.0 * std::numbers::pi * d / k;
    dx[d] = std::cos(angle);
    dy[d] = std::sin(angle);
    best[d] = -std::numeric_limits<double>::infinity();
    at[d] = 0;
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const double x = points[i].x(), y = points[i].y();
    for (int d = 0; d < k; ++d) {
      const double v = dx[d] * x + dy[d] * y;
      const bool better = v > best[d];
      best[d] = better ? v : best[d];
      at[d] = better ? i : at[d];
    }
  }
  // In order of direction, the extremes make a convex polygon, counter-clockwise
  // (a point may be extreme in several directions).
  Vec2 poly[k];
  int m = 0;
  for (int d = 0; d < k; ++d) {
    const Vec2& q = points[at[d]];
    if (m == 0 || q != poly[m - 1]) poly[m++] = q;
  }
  while (m > 1 && poly[m - 1] == poly[0]) --m;
  if (m < 3) return points;
  // Edge e: from (px, py) along (ex, ey); unused slots repeat edge 0.
  double px[k], py[k], ex[k], ey[k];
  for (int e = 0; e < k; ++e) {
    const int f = e < m ? e : 0;
    px[e] = poly[f].x();
    py[e] = poly[f].y();
    ex[e] = poly[(f + 1) % m].x() - px[e];
    ey[e] = poly[(f + 1) % m].y() - py[e];
  }
  std::vector<Vec2> out;
  for (const Vec2& q : points) {
    const double x = q.x(), y = q.y();
    int inside = 1;
    for (int e = 0; e < k; ++e) inside &= ex[e] * (y - py[e]) - ey[e] * (x - px[e]) > 0.0;
    if (!inside) out.push_back(q);
  }
  return out;
}

// Convex hull (Andrew's monotone chain), counter-clockwise. Points that cannot
// be on the hull are dropped before sorting, with 8 directions and then, among
// the survivors, 32: a fine model keeps a few percent of its points for the
// sort (the measurements are in BENCHMARKS.md).
std::vector<Vec2> ConvexHull(const std::vector<Vec2>& points) {
  std::vector<Vec2> p = points.size() > 64 ? DropInterior<32>(DropInterior<8>(points)) : points;
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Vec2> h(2 * p.size());
  size_t k = 0;
  auto turn = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && turn(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && turn(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// The grid columns (i + s) and rows (j + t) that located points of a sheet
// cover: on a sheet continued past its seams, how far round the surface
// they go.
struct GridSpan {
  Eigen::AlignedBox2d box;
  void Add(const SheetLocation& l) { box.extend(Vec2(l.i + l.s, l.j + l.t)); }
  double columns() const { return box.isEmpty() ? 0.0 : box.sizes().x(); }
  double rows() const { return box.isEmpty() ? 0.0 : box.sizes().y(); }
  // The most times round a closed direction of `map` (0 when none is).
  double Turns(const SheetMap& map) const {
    double turns = 0.0;
    if (map.period_columns() > 0) turns = columns() / map.period_columns();
    if (map.period_rows() > 0) turns = std::max(turns, rows() / map.period_rows());
    return turns;
  }
};

// The footprint's outline for fitting: its convex hull, and its farthest
// point from the footprint centre.
struct Outline {
  std::vector<Vec2> hull;
  double extent = 0.0;
};

Result<Outline> OutlineOf(const std::vector<Vec2>& footprint, const Vec2& centre) {
  Outline o;
  o.hull = ConvexHull(footprint);
  for (const Vec2& p : o.hull) o.extent = std::max(o.extent, (p - centre).norm());
  if (!(o.extent > 0.0)) {
    return Degenerate("the model's footprint is a single point: nothing to fit", "placement.scale");
  }
  return o;
}

// Whether the outline, placed by `base` at scale s, stays inside the sheet at
// least `margin` from its boundary. Outline samples at most `spacing` apart:
// when every sample is inside and at least `margin` from the boundary, every
// point of the outline is at least margin - spacing / 2 > 0 from it. The sheet
// is simply connected, so an outline inside it encloses only sheet points.
//
// On a sheet continued past its seams (SheetMap::periodic_u, periodic_v),
// the outline must also span at most one period of columns (rows): a
// longer model would lie on the surface over itself. The footprint's extent
// round the surface is its outline's, on a cylinder's strip and on a cone's
// sector alike.
bool OutlineInside(const SheetMap& map, const Outline& outline, const Placement& base, double s,
                   double margin) {
  const FlatLocator& locator = map.locator();
  const std::vector<Vec2>& hull = outline.hull;
  const double spacing =
      margin > 0.0 ? margin : 0.01 * map.given_locator().bounds().sizes().minCoeff();  // 1%
  const bool periodic = map.period_columns() > 0 || map.period_rows() > 0;
  GridSpan span;
  int hint = -1;
  for (size_t k = 0; k < hull.size(); ++k) {
    const Vec2 a = base.target + s * (base.rotation * (hull[k] - base.centre));
    const Vec2 b = base.target + s * (base.rotation * (hull[(k + 1) % hull.size()] - base.centre));
    const int steps = ClampedCeil((b - a).norm() / spacing, 1, 4096);
    for (int q = 0; q < steps; ++q) {
      const Vec2 placed = a + (b - a) * (static_cast<double>(q) / steps);
      SheetLocation l;
      if (!locator.Locate(placed, &l, &hint)) return false;
      if (locator.BoundaryWithin(placed, margin)) return false;
      if (const std::optional<double> depth = map.DomainDepth(placed)) {
        if (!(*depth > 0.0 && *depth >= margin)) return false;  // off a mesh's flat triangles
      }
      if (periodic) {
        span.Add(l);
        if (span.Turns(map) > 1.0) return false;
      }
    }
  }
  return true;
}

// The largest scale up to `hi` at which the outline stays inside the sheet
// (OutlineInside), to a relative 1e-5: far below the margin's own precision.
Result<double> FitScale(const SheetMap& map, const Outline& outline, const Placement& base,
                        double margin, double hi) {
  if (!OutlineInside(map, outline, base, 0.0, margin)) {
    return Status(ErrorCode::kOutsideSheet,
                  "the footprint's centre is not inside the flat sheet (with the margin), so no "
                  "scale fits; move placement.center",
                  "placement.center");
  }
  double lo = 0.0;
  for (int it = 0; it < 60 && hi - lo > 1e-5 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (OutlineInside(map, outline, base, mid, margin) ? lo : hi) = mid;
  }
  return lo;
}

// Where the footprint's centre goes on the map's given sheet: the image of
// (u, v) = (1/2, 1/2), a sheet point, or a fraction of the sheet's box.
Vec2 TargetOn(const SheetMap& map, const PlacementOptions& o) {
  const FlatLocator& locator = map.given_locator();
  const FlatSheet& sheet = map.given_sheet();
  switch (o.center_mode) {
    case CenterMode::kSheetCenter: {
      // The image of the surface's parameter midpoint (u, v) = (1/2, 1/2):
      // inside the sheet whatever its shape (the middle of a bounding box is
      // not, for an unrolled cone).
      const double gu = 0.5 * (sheet.nu - 1);
      const double gv = 0.5 * (sheet.nv - 1);
      SheetLocation mid;
      mid.i = std::min(static_cast<int>(gu), sheet.nu - 2);
      mid.j = std::min(static_cast<int>(gv), sheet.nv - 2);
      mid.s = gu - mid.i;
      mid.t = gv - mid.j;
      return locator.FlatPoint(mid);
    }
    case CenterMode::kSheetUnits:
      return o.center;
    case CenterMode::kFraction:
      break;
  }
  const Eigen::AlignedBox2d& sb = locator.bounds();
  return sb.min() + o.center.cwiseProduct(sb.sizes());
}

// How far a numeric anchor may lie outside the model's heights, in model
// sizes: further, the model floats off the surface by more than it is
// worth bending (and its offset surface's refinement runs away).
constexpr double kMaxAnchorOffsetInSizes = 10.0;

// The placement on the map's given sheet before any fit (scale as given),
// and the footprint (a, b) of every vertex when asked for. kInvalidArgument
// for a numeric anchor past kMaxAnchorOffsetInSizes.
Result<Placement> Unfitted(const SheetMap& map, const std::vector<Vec3>& positions,
                           const PlacementOptions& o, std::vector<Vec2>* footprint) {
  const size_t n = positions.size();
  Placement pl;
  pl.up = ResolveUpAxis(o.up, o.y_up_input, positions, &pl.up_reason);
  pl.basis = AxisBasis(pl.up);
  Eigen::AlignedBox3d box;
  if (footprint != nullptr) footprint->resize(n);
  for (size_t k = 0; k < n; ++k) {
    const Vec3 q = pl.basis * positions[k];
    box.extend(q);
    if (footprint != nullptr) (*footprint)[k] = q.head<2>();
  }
  if (n == 0) box.extend(Vec3::Zero());
  pl.centre = o.centre_at_origin ? Vec2::Zero().eval()
                                 : Vec2(0.5 * (box.min().head<2>() + box.max().head<2>()));
  switch (o.anchor) {
    case AnchorMode::kBottom:
      pl.h0 = box.min().z();
      break;
    case AnchorMode::kCenter:
      pl.h0 = 0.5 * (box.min().z() + box.max().z());
      break;
    case AnchorMode::kTop:
      pl.h0 = box.max().z();
      break;
    case AnchorMode::kValue: {
      pl.h0 = o.anchor_value;
      const double size = (box.max() - box.min()).maxCoeff();
      const double off = std::max(box.min().z() - o.anchor_value, o.anchor_value - box.max().z());
      if (size > 0.0 && off > kMaxAnchorOffsetInSizes * size) {
        return InvalidArgument("lies " + Num(off) +
                                   " model units outside the model's heights, over " +
                                   Num(kMaxAnchorOffsetInSizes) + " times its size (" + Num(size) +
                                   "): the model would float off the surface; give "
                                   "a height within the model, or \"bottom\", \"center\" or "
                                   "\"top\"",
                               "placement.anchor");
      }
      break;
    }
  }
  const double angle = o.rotation_deg * std::numbers::pi / 180.0;
  pl.rotation << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  pl.target = TargetOn(map, o);
  pl.scale = o.scale;
  return pl;
}

// fit's margin on a sheet: a fraction of its bounding box's smaller side.
double FitMargin(const SheetMap& map, const PlacementOptions& o) {
  return o.fit_margin * map.given_locator().bounds().sizes().minCoeff();
}

// The largest scale worth trying on a sheet: the footprint spans its box.
double LargestScale(const SheetMap& map, const Outline& outline) {
  return map.locator().bounds().diagonal().norm() / outline.extent;
}

}  // namespace

Status ValidatePlacementSettings(const PlacementSettings& o) {
  if (!std::isfinite(o.anchor_value)) {
    return InvalidArgument("must be a finite number", "placement.anchor");
  }
  if (!o.center.allFinite()) return InvalidArgument("must be finite", "placement.center");
  if (o.center.cwiseAbs().maxCoeff() > kMaxSurfaceNumber) {
    return InvalidArgument("must be within +-" + Num(kMaxSurfaceNumber) + ", got " +
                               Num(o.center.cwiseAbs().maxCoeff()),
                           "placement.center");
  }
  if (std::abs(o.anchor_value) > kMaxSurfaceNumber) {
    return InvalidArgument(
        "must be within +-" + Num(kMaxSurfaceNumber) + ", got " + Num(o.anchor_value),
        "placement.anchor");
  }
  if (!std::isfinite(o.rotation_deg)) {
    return InvalidArgument("must be a finite number", "placement.rotation_deg");
  }
  if (!o.fit && !(std::isfinite(o.scale) && o.scale > 0.0)) {
    return InvalidArgument("must be a positive finite number or \"fit\", got " + Num(o.scale),
                           "placement.scale");
  }
  if (!(o.fit_margin >= 0.0 && o.fit_margin < 0.5)) {
    return InvalidArgument("must be in [0, 0.5), got " + Num(o.fit_margin), "placement.fit_margin");
  }
  return Status::Ok();
}

Status ValidatePlacement(const PlacementOptions& o) {
  SURFDEFORM_RETURN_IF_ERROR(ValidatePlacementSettings(o));
  if (o.threads < 0 || o.threads > 256) {
    return InvalidArgument("must be from 0 to 256", "placement.threads");
  }
  return Status::Ok();
}

UpAxis ResolveUpAxis(UpAxis up, bool y_up_input, const std::vector<Vec3>& positions,
                     const char** reason) {
  *reason = "given";
  if (up != UpAxis::kAuto) return up;
  if (y_up_input) {
    *reason = "gltf";
    return UpAxis::kPosY;
  }
  Eigen::AlignedBox3d box;
  for (const Vec3& p : positions) box.extend(p);
  *reason = "default";
  if (box.isEmpty()) return UpAxis::kPosZ;
  const Vec3 size = box.sizes();
  int thin = 0;
  size.minCoeff(&thin);
  const double next = std::min(size[(thin + 1) % 3], size[(thin + 2) % 3]);
  if (!(size[thin] <= 0.5 * next)) return UpAxis::kPosZ;
  *reason = "thinnest";
  constexpr UpAxis kPositive[3] = {UpAxis::kPosX, UpAxis::kPosY, UpAxis::kPosZ};
  return kPositive[thin];
}

Result<Placement> ComputePlacement(const SheetMap& map, const std::vector<Vec3>& positions,
                                   const PlacementOptions& o) {
  std::vector<Vec2> footprint;
  SURFDEFORM_ASSIGN_OR_RETURN(Placement pl,
                              Unfitted(map, positions, o, o.fit ? &footprint : nullptr));
  if (!o.fit) return pl;
  SURFDEFORM_ASSIGN_OR_RETURN(const Outline outline, OutlineOf(footprint, pl.centre));
  SURFDEFORM_ASSIGN_OR_RETURN(
      pl.scale, FitScale(map, outline, pl, FitMargin(map, o), LargestScale(map, outline)));
  return pl;
}

double TurnsRound(const SheetMap& map, const Placement& pl, std::span<const Vec3> positions) {
  if ((!map.periodic_u() && !map.periodic_v()) || positions.empty()) return 0.0;
  std::vector<Vec2> footprint(positions.size());
  for (size_t k = 0; k < positions.size(); ++k) footprint[k] = pl.Apply(positions[k]).head<2>();
  GridSpan span;
  int hint = -1;
  for (const Vec2& p : ConvexHull(footprint)) {
    SheetLocation l;
    if (map.locator().Locate(p, &l, &hint)) span.Add(l);  // off the sheet: reported as such
  }
  return span.Turns(map);
}

Result<FramePlacements> ComputeFramePlacements(std::span<const SheetMap* const> maps,
                                               const std::vector<Vec3>& positions,
                                               const PlacementOptions& o) {
  FramePlacements out;
  if (maps.empty()) return out;
  // What depends on the model (axes, footprint, anchor) once; the target on
  // every frame's sheet.
  std::vector<Vec2> footprint;
  SURFDEFORM_ASSIGN_OR_RETURN(const Placement first,
                              Unfitted(*maps.front(), positions, o, o.fit ? &footprint : nullptr));
  out.each.assign(maps.size(), first);
  for (size_t k = 1; k < maps.size(); ++k) out.each[k].target = TargetOn(*maps[k], o);
  if (!o.fit) return out;
  SURFDEFORM_ASSIGN_OR_RETURN(const Outline outline, OutlineOf(footprint, out.each[0].centre));
  // Each frame is fitted only when the scale so far does not fit it: the
  // tightest frame decides, in one bisection for most sequences.
  double scale = 0.0;
  for (size_t k = 0; k < maps.size(); ++k) {
    const SheetMap& map = *maps[k];
    const double margin = FitMargin(map, o);
    if (out.fit_frame >= 0 && OutlineInside(map, outline, out.each[k], scale, margin)) continue;
    const double hi = out.fit_frame >= 0 ? scale : LargestScale(map, outline);
    auto fitted = FitScale(map, outline, out.each[k], margin, hi);
    if (!fitted.ok()) {
      return Status(fitted.status().code(),
                    "frame " + std::to_string(k) + ": " + fitted.status().message(),
                    fitted.status().field());
    }
    scale = *fitted;
    out.fit_frame = static_cast<int>(k);
  }
  for (Placement& pl : out.each) pl.scale = scale;
  return out;
}

}  // namespace surfdeform
