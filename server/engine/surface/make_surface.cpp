// Validation of surface specs and dispatch to the surface builders.
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <iterator>
#include <numbers>
#include <sstream>
#include <string>
#include <variant>

#include "base/format.hpp"
#include "engine/surface/analytic_surfaces.hpp"
#include "engine/surface/bspline_basis.hpp"
#include "engine/surface/mesh_surface.hpp"
#include "engine/surface/spline_surface.hpp"
#include "engine/surface/surface_fields.hpp"
#include "engine/surface/surface_spec.hpp"

namespace surfdeform {
namespace {

constexpr int kMaxBezierDegree = 15;
constexpr int kMaxBSplineDegree = 7;
constexpr int kMaxGridSide = 1024;
constexpr size_t kMaxControlPoints = 1u << 20;

Status CheckFinite(double x, const std::string& field) {
  if (!std::isfinite(x))
    return InvalidArgument("must be a finite number, got " + Num(x, 17), field);
  return Status::Ok();
}

Status CheckPositive(double x, const std::string& field) {
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(x, field));
  if (!(x > 0.0)) return InvalidArgument("must be greater than 0, got " + Num(x, 17), field);
  return Status::Ok();
}

Status CheckRange(double x, double lo, double hi, const std::string& field) {
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(x, field));
  if (x < lo || x > hi) {
    return InvalidArgument(
        "must be in [" + Num(lo, 17) + ", " + Num(hi, 17) + "], got " + Num(x, 17), field);
  }
  return Status::Ok();
}

Status CheckPoints(const std::vector<Vec3>& points, const std::string& field) {
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      return InvalidArgument("coordinates must be finite numbers",
                             field + "[" + std::to_string(i) + "]");
    }
  }
  // A collapsed net (all points equal) has no normal anywhere.
  Eigen::AlignedBox3d box;
  for (const Vec3& p : points) box.extend(p);
  if (!points.empty() && !(box.diagonal().norm() > 0.0)) {
    return Degenerate("all points coincide: the surface has no area", field);
  }
  return Status::Ok();
}

Status CheckDegree(int degree, int max_degree, const std::string& field) {
  if (degree < 1 || degree > max_degree) {
    return InvalidArgument("must be an integer from 1 to " + std::to_string(max_degree) + ", got " +
                               std::to_string(degree),
                           field);
  }
  return Status::Ok();
}

Result<RigidFrame> BuildFrame(const Frame& f) {
  if (!f.origin.allFinite()) return InvalidArgument("must be finite", "frame.origin");
  if (!f.x_axis.allFinite()) return InvalidArgument("must be finite", "frame.x_axis");
  if (!f.z_axis.allFinite()) return InvalidArgument("must be finite", "frame.z_axis");
  const double zn = f.z_axis.norm();
  const double xn = f.x_axis.norm();
  if (!(zn > 0.0)) return Degenerate("must not be the zero vector", "frame.z_axis");
  if (!(xn > 0.0)) return Degenerate("must not be the zero vector", "frame.x_axis");
  const Vec3 z = f.z_axis / zn;
  Vec3 x = f.x_axis / xn;
  x -= z * z.dot(x);
  if (!(x.norm() > 1e-9)) {
    return Degenerate("must not be parallel to frame.z_axis", "frame.x_axis");
  }
  x.normalize();
  RigidFrame out;
  out.origin = f.origin;
  out.rotation.col(0) = x;
  out.rotation.col(1) = z.cross(x);
  out.rotation.col(2) = z;
  return out;
}

// `periodic`: the knot vector need not be clamped (a periodic spline's is
// uniform and unclamped).
Status CheckKnots(const std::vector<double>& knots, int count, int degree, const std::string& field,
                  bool periodic = false) {
  const size_t expected = static_cast<size_t>(count) + degree + 1;
  if (knots.size() != expected) {
    return InvalidArgument("needs count + degree + 1 = " + std::to_string(expected) +
                               " values, got " + std::to_string(knots.size()),
                           field);
  }
  for (size_t i = 0; i < knots.size(); ++i) {
    SURFDEFORM_RETURN_IF_ERROR(CheckFinite(knots[i], field + "[" + std::to_string(i) + "]"));
    if (i > 0 && knots[i] < knots[i - 1]) {
      return InvalidArgument("knots must be non-decreasing: " + Num(knots[i], 17) + " follows " +
                                 Num(knots[i - 1], 17),
                             field + "[" + std::to_string(i) + "]");
    }
  }
  for (int i = 1; i <= degree && !periodic; ++i) {
    if (knots[i] != knots[0] || knots[count + i] != knots[count]) {
      return InvalidArgument("the knot vector must be clamped: its first and last " +
                                 std::to_string(degree + 1) +
                                 " values must be equal (or set periodic_u for a closed surface)",
                             field);
    }
  }
  if (!(knots[count] > knots[degree])) {
    return Degenerate("the knot range is empty (first knot equals last knot)", field);
  }
  // Interior multiplicity above the degree would make the surface discontinuous.
  for (int i = degree + 1; i < count;) {
    int j = i;
    while (j < count && knots[j] == knots[i]) ++j;
    if (j - i > degree) {
      return InvalidArgument("interior knot " + Num(knots[i], 17) + " repeats " +
                                 std::to_string(j - i) + " times; at most the degree (" +
                                 std::to_string(degree) + ") keeps the surface continuous",
                             field + "[" + std::to_string(i) + "]");
    }
    i = j;
  }
  return Status::Ok();
}

// A surface declared periodic in u (`in_v` false) or v must close:
// S(0, v) = S(1, v) (or S(u, 0) = S(u, 1)) to 1e-9 of the size of `points`
// (its control net or grid). `seam` gives the gap and where along the seam
// it is largest.
Status CheckSeamCloses(const std::vector<Vec3>& points, bool in_v,
                       const std::function<double(double* at)>& seam) {
  Eigen::AlignedBox3d box;
  for (const Vec3& p : points) box.extend(p);
  const double size = box.diagonal().norm();
  double at = 0.0;
  const double gap = seam(&at);
  if (!(gap <= 1e-9 * size)) {
    std::string message = "the surface does not close in ";
    message += in_v ? "v: its seam (v = 0 against v = 1)" : "u: its seam (u = 0 against u = 1)";
    message += " fails to meet by " + Num(gap, 17) + (in_v ? " at u = " : " at v = ") + Num(at, 17);
    message += " (" + Num(gap / size, 17) + " of its size; at most 1e-9). Make the last ";
    message += in_v ? "row of points repeat the first, or leave periodic_v false"
                    : "column of points repeat the first, or leave periodic_u false";
    return InvalidArgument(message, in_v ? "periodic_v" : "periodic_u");
  }
  return Status::Ok();
}

// The largest gap across the seam in u (or v), sampled along it at and
// between the `lines` (rows or columns of the net).
double SurfaceSeamGap(const Surface& surface, bool in_v, int lines, double* at) {
  const int samples = std::max(64, 4 * lines);
  double gap = 0.0;
  for (int k = 0; k <= samples; ++k) {
    const double t = static_cast<double>(k) / samples;
    const double d = in_v ? (surface.Position(t, 0.0) - surface.Position(t, 1.0)).norm()
                          : (surface.Position(0.0, t) - surface.Position(1.0, t)).norm();
    if (d > gap) {
      gap = d;
      *at = t;
    }
  }
  return gap;
}

// The largest gap between a grid's first and last column (or row).
double GridSeamGap(const GridSpec& s, bool in_v, double* at) {
  const int lines = in_v ? s.nu : s.nv;
  double gap = 0.0;
  for (int k = 0; k < lines; ++k) {
    const Vec3& a = in_v ? s.points[k] : s.points[s.nu * k];
    const Vec3& b = in_v ? s.points[k + s.nu * (s.nv - 1)] : s.points[s.nu - 1 + s.nu * k];
    if ((a - b).norm() > gap) {
      gap = (a - b).norm();
      *at = static_cast<double>(k) / (lines - 1);
    }
  }
  return gap;
}

Result<std::unique_ptr<Surface>> Build(const BezierSpec& s) {
  SURFDEFORM_RETURN_IF_ERROR(CheckDegree(s.degree_u, kMaxBezierDegree, "degree_u"));
  SURFDEFORM_RETURN_IF_ERROR(CheckDegree(s.degree_v, kMaxBezierDegree, "degree_v"));
  const size_t nu = s.degree_u + 1, nv = s.degree_v + 1;
  if (s.control_points.size() != nu * nv) {
    return InvalidArgument("a degree " + std::to_string(s.degree_u) + " x " +
                               std::to_string(s.degree_v) + " Bezier patch needs " +
                               std::to_string(nu * nv) + " control points, got " +
                               std::to_string(s.control_points.size()),
                           "control_points");
  }
  SURFDEFORM_RETURN_IF_ERROR(CheckPoints(s.control_points, "control_points"));
  SplineData d;
  d.degree_u = s.degree_u;
  d.degree_v = s.degree_v;
  d.count_u = static_cast<int>(nu);
  d.count_v = static_cast<int>(nv);
  d.control_points = s.control_points;
  d.knots_u.assign(2 * nu, 0.0);
  d.knots_v.assign(2 * nv, 0.0);
  std::fill(d.knots_u.begin() + nu, d.knots_u.end(), 1.0);
  std::fill(d.knots_v.begin() + nv, d.knots_v.end(), 1.0);
  return MakeSplineSurface(std::move(d), "bezier");
}

Result<std::unique_ptr<Surface>> Build(const BSplineSpec& s) {
  SURFDEFORM_RETURN_IF_ERROR(CheckDegree(s.degree_u, kMaxBSplineDegree, "degree_u"));
  SURFDEFORM_RETURN_IF_ERROR(CheckDegree(s.degree_v, kMaxBSplineDegree, "degree_v"));
  if (s.count_u <= s.degree_u || s.count_u > kMaxGridSide) {
    return InvalidArgument("must be from degree_u + 1 = " + std::to_string(s.degree_u + 1) +
                               " to " + std::to_string(kMaxGridSide) + ", got " +
                               std::to_string(s.count_u),
                           "count_u");
  }
  if (s.count_v <= s.degree_v || s.count_v > kMaxGridSide) {
    return InvalidArgument("must be from degree_v + 1 = " + std::to_string(s.degree_v + 1) +
                               " to " + std::to_string(kMaxGridSide) + ", got " +
                               std::to_string(s.count_v),
                           "count_v");
  }
  const size_t n = static_cast<size_t>(s.count_u) * s.count_v;
  if (n > kMaxControlPoints || s.control_points.size() != n) {
    return InvalidArgument("count_u * count_v = " + std::to_string(n) +
                               " control points expected, got " +
                               std::to_string(s.control_points.size()),
                           "control_points");
  }
  SURFDEFORM_RETURN_IF_ERROR(CheckPoints(s.control_points, "control_points"));
  SURFDEFORM_RETURN_IF_ERROR(CheckKnots(s.knots_u, s.count_u, s.degree_u, "knots_u", s.periodic_u));
  SURFDEFORM_RETURN_IF_ERROR(CheckKnots(s.knots_v, s.count_v, s.degree_v, "knots_v", s.periodic_v));
  if (s.rational && s.weights.size() != n) {
    return InvalidArgument("a NURBS needs one weight per control point (" + std::to_string(n) +
                               "), got " + std::to_string(s.weights.size()),
                           "weights");
  }
  if (!s.rational && !s.weights.empty()) {
    return InvalidArgument("a non-rational B-spline takes no weights (use kind \"nurbs\")",
                           "weights");
  }
  for (size_t i = 0; i < s.weights.size(); ++i) {
    SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.weights[i], "weights[" + std::to_string(i) + "]"));
  }
  SplineData d;
  d.degree_u = s.degree_u;
  d.degree_v = s.degree_v;
  d.count_u = s.count_u;
  d.count_v = s.count_v;
  d.control_points = s.control_points;
  d.knots_u = s.knots_u;
  d.knots_v = s.knots_v;
  d.weights = s.weights;
  d.closed_u = s.periodic_u;
  d.closed_v = s.periodic_v;
  auto surface = MakeSplineSurface(std::move(d), s.rational ? "nurbs" : "bspline");
  for (const bool in_v : {false, true}) {
    if (!(in_v ? s.periodic_v : s.periodic_u)) continue;
    SURFDEFORM_RETURN_IF_ERROR(CheckSeamCloses(s.control_points, in_v, [&](double* at) {
      return SurfaceSeamGap(*surface, in_v, in_v ? s.count_u : s.count_v, at);
    }));
  }
  return surface;
}

Result<std::unique_ptr<Surface>> Build(const MeshSpec& s) {
  if (s.flattened == nullptr) {
    return Status(ErrorCode::kInternal, "the mesh surface was not resolved before it was built",
                  "model_id");
  }
  return std::unique_ptr<Surface>(std::make_unique<MeshSurface>(s.flattened));
}

Result<std::unique_ptr<Surface>> Build(const GridSpec& s) {
  for (auto [n, name] : {std::pair{s.nu, "nu"}, std::pair{s.nv, "nv"}}) {
    if (n < 2 || n > kMaxGridSide) {
      return InvalidArgument(
          "must be from 2 to " + std::to_string(kMaxGridSide) + ", got " + std::to_string(n), name);
    }
  }
  const size_t n = static_cast<size_t>(s.nu) * s.nv;
  if (s.points.size() != n) {
    return InvalidArgument("nu * nv = " + std::to_string(n) + " points expected, got " +
                               std::to_string(s.points.size()),
                           "points");
  }
  SURFDEFORM_RETURN_IF_ERROR(CheckPoints(s.points, "points"));
  for (const bool in_v : {false, true}) {
    if (!(in_v ? s.periodic_v : s.periodic_u)) continue;
    if ((in_v ? s.nv : s.nu) < 4) {
      return InvalidArgument(std::string("a grid closed in ") + (in_v ? "v" : "u") +
                                 " needs at least 4 points that way (3 and the first again), got " +
                                 std::to_string(in_v ? s.nv : s.nu),
                             in_v ? "nv" : "nu");
    }
    SURFDEFORM_RETURN_IF_ERROR(
        CheckSeamCloses(s.points, in_v, [&](double* at) { return GridSeamGap(s, in_v, at); }));
  }
  // Interpolate along u (each row j), then along v (each control column).
  Eigen::MatrixXd rows(s.nu, 3 * s.nv);
  for (int j = 0; j < s.nv; ++j) {
    for (int i = 0; i < s.nu; ++i) rows.block<1, 3>(i, 3 * j) = s.points[i + s.nu * j].transpose();
  }
  SplineData d;
  d.degree_u = d.degree_v = 3;
  d.count_u = s.nu + 2;
  d.count_v = s.nv + 2;
  const Eigen::MatrixXd cu = s.periodic_u
                                 ? InterpolateCubicPeriodic(rows, &d.knots_u)
                                 : InterpolateCubicNatural(rows, &d.knots_u);  // (nu+2) x 3nv
  Eigen::MatrixXd cols(s.nv, 3 * d.count_u);
  for (int j = 0; j < s.nv; ++j) {
    for (int i = 0; i < d.count_u; ++i) cols.block<1, 3>(j, 3 * i) = cu.block<1, 3>(i, 3 * j);
  }
  const Eigen::MatrixXd cv = s.periodic_v
                                 ? InterpolateCubicPeriodic(cols, &d.knots_v)
                                 : InterpolateCubicNatural(cols, &d.knots_v);  // (nv+2) x 3(nu+2)
  d.control_points.resize(static_cast<size_t>(d.count_u) * d.count_v);
  for (int j = 0; j < d.count_v; ++j) {
    for (int i = 0; i < d.count_u; ++i) {
      d.control_points[i + d.count_u * j] = cv.block<1, 3>(j, 3 * i).transpose();
    }
  }
  d.closed_u = s.periodic_u;
  d.closed_v = s.periodic_v;
  return MakeSplineSurface(std::move(d), "grid");
}

Status CheckAngleSpan(double lo, double hi, const std::string& lo_field,
                      const std::string& hi_field) {
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(lo, lo_field));
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(hi, hi_field));
  if (!(hi > lo)) {
    return InvalidArgument(
        "must be greater than " + lo_field + " (" + Num(lo, 17) + "), got " + Num(hi, 17),
        hi_field);
  }
  if (hi - lo > 360.0) {
    return InvalidArgument(
        "the span " + hi_field + " - " + lo_field + " must be at most 360, got " + Num(hi - lo, 17),
        hi_field);
  }
  return Status::Ok();
}

Result<std::unique_ptr<Surface>> Build(const CylinderSpec& s) {
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.radius, "radius"));
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.height, "height"));
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.angle_deg, "angle_deg"));
  SURFDEFORM_RETURN_IF_ERROR(CheckRange(s.angle_deg, 0.0, 360.0, "angle_deg"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto frame, BuildFrame(s.frame));
  return MakeCylinder(s, frame);
}

Result<std::unique_ptr<Surface>> Build(const ConeSpec& s) {
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(s.radius_bottom, "radius_bottom"));
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(s.radius_top, "radius_top"));
  if (s.radius_bottom < 0.0) return InvalidArgument("must not be negative", "radius_bottom");
  if (s.radius_top < 0.0) return InvalidArgument("must not be negative", "radius_top");
  if (!(s.radius_bottom > 0.0 || s.radius_top > 0.0)) {
    return Degenerate("radius_bottom and radius_top are both 0: the cone is a line",
                      "radius_bottom");
  }
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.height, "height"));
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.angle_deg, "angle_deg"));
  SURFDEFORM_RETURN_IF_ERROR(CheckRange(s.angle_deg, 0.0, 360.0, "angle_deg"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto frame, BuildFrame(s.frame));
  return MakeCone(s, frame);
}

Result<std::unique_ptr<Surface>> Build(const SphereSpec& s) {
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.radius, "radius"));
  SURFDEFORM_RETURN_IF_ERROR(
      CheckAngleSpan(s.lon_min_deg, s.lon_max_deg, "lon_min_deg", "lon_max_deg"));
  SURFDEFORM_RETURN_IF_ERROR(CheckRange(s.lat_min_deg, -90.0, 90.0, "lat_min_deg"));
  SURFDEFORM_RETURN_IF_ERROR(CheckRange(s.lat_max_deg, -90.0, 90.0, "lat_max_deg"));
  SURFDEFORM_RETURN_IF_ERROR(
      CheckAngleSpan(s.lat_min_deg, s.lat_max_deg, "lat_min_deg", "lat_max_deg"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto frame, BuildFrame(s.frame));
  return MakeSphere(s, frame);
}

// A horn or spindle torus (minor_radius >= major_radius) reaches its axis
// where R + r cos(v) = 0: there the surface pinches to a point (its normal
// vanishes, and a spindle's tube passes through itself). Decided from the
// radii and the v span, whatever the sampling: kDegenerate when the span
// holds such a v.
Status CheckTorusClearsItsAxis(const TorusSpec& s) {
  if (s.minor_radius < s.major_radius) return Status::Ok();
  const double pinch = std::acos(-s.major_radius / s.minor_radius) * 180.0 / std::numbers::pi;
  for (double at : {pinch, -pinch}) {
    // The first angle congruent to `at` at or past v_min_deg.
    const double k = std::ceil((s.v_min_deg - at) / 360.0 - 1e-12);
    const double v = at + 360.0 * k;
    if (v <= s.v_max_deg + 1e-12) {
      return Degenerate(
          "the tube (minor_radius " + Num(s.minor_radius, 17) +
              ") reaches the axis (major_radius " + Num(s.major_radius, 17) +
              ") at v = " + Num(v, 17) +
              " degrees, where the surface pinches to a point; use a minor_radius below the "
              "major_radius, or a v span without it",
          "minor_radius");
    }
  }
  return Status::Ok();
}

Result<std::unique_ptr<Surface>> Build(const TorusSpec& s) {
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.major_radius, "major_radius"));
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.minor_radius, "minor_radius"));
  SURFDEFORM_RETURN_IF_ERROR(CheckAngleSpan(s.u_min_deg, s.u_max_deg, "u_min_deg", "u_max_deg"));
  SURFDEFORM_RETURN_IF_ERROR(CheckAngleSpan(s.v_min_deg, s.v_max_deg, "v_min_deg", "v_max_deg"));
  SURFDEFORM_RETURN_IF_ERROR(CheckTorusClearsItsAxis(s));
  SURFDEFORM_ASSIGN_OR_RETURN(auto frame, BuildFrame(s.frame));
  return MakeTorus(s, frame);
}

Result<std::unique_ptr<Surface>> Build(const WaveSpec& s) {
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.length, "length"));
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.width, "width"));
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(s.amplitude, "amplitude"));
  SURFDEFORM_RETURN_IF_ERROR(CheckPositive(s.wavelength, "wavelength"));
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(s.speed, "speed"));
  SURFDEFORM_RETURN_IF_ERROR(CheckFinite(s.time, "time"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto frame, BuildFrame(s.frame));
  return MakeWave(s, frame);
}

}  // namespace

bool ClosesInU(const SurfaceSpec& spec) {
  constexpr double kTurn = 360.0 * (1.0 - 1e-12);  // as Surface::ClosedInU, in degrees
  if (const auto* c = std::get_if<CylinderSpec>(&spec)) return c->angle_deg >= kTurn;
  if (const auto* c = std::get_if<ConeSpec>(&spec)) return c->angle_deg >= kTurn;
  if (const auto* s = std::get_if<SphereSpec>(&spec))
    return s->lon_max_deg - s->lon_min_deg >= kTurn;
  if (const auto* t = std::get_if<TorusSpec>(&spec)) return t->u_max_deg - t->u_min_deg >= kTurn;
  if (const auto* b = std::get_if<BSplineSpec>(&spec)) return b->periodic_u;
  if (const auto* g = std::get_if<GridSpec>(&spec)) return g->periodic_u;
  return false;
}

bool ClosesInV(const SurfaceSpec& spec) {
  constexpr double kTurn = 360.0 * (1.0 - 1e-12);
  if (const auto* t = std::get_if<TorusSpec>(&spec)) return t->v_max_deg - t->v_min_deg >= kTurn;
  if (const auto* b = std::get_if<BSplineSpec>(&spec)) return b->periodic_v;
  if (const auto* g = std::get_if<GridSpec>(&spec)) return g->periodic_v;
  return false;
}

SurfaceKind KindOf(const SurfaceSpec& spec) {
  static constexpr SurfaceKind kByIndex[] = {
      SurfaceKind::kBezier, SurfaceKind::kBSpline, SurfaceKind::kCylinder,
      SurfaceKind::kCone,   SurfaceKind::kSphere,  SurfaceKind::kTorus,
      SurfaceKind::kWave,   SurfaceKind::kGrid,    SurfaceKind::kMesh};
  static_assert(std::size(kByIndex) == std::variant_size_v<SurfaceSpec>);
  if (const auto* b = std::get_if<BSplineSpec>(&spec); b != nullptr && b->rational) {
    return SurfaceKind::kNurbs;
  }
  return kByIndex[spec.index()];
}

Result<std::unique_ptr<Surface>> MakeSurface(const SurfaceSpec& spec) {
  // Sizes past kMaxSurfaceNumber overflow the derivatives' products (the
  // normal is Su x Sv): refused as what they are, not as a vanishing normal.
  Status bounded = Status::Ok();
  WalkNumbers(spec, [&](const auto& name, const double& v) {
    if (bounded.ok() && std::isfinite(v) && std::abs(v) > kMaxSurfaceNumber) {
      bounded = InvalidArgument(Format("must be within +-%g (larger sizes overflow the "
                                       "surface's derivatives), got %g",
                                       kMaxSurfaceNumber, v),
                                name());
    }
  });
  SURFDEFORM_RETURN_IF_ERROR(bounded);
  return std::visit([](const auto& s) { return Build(s); }, spec);
}

}  // namespace surfdeform
