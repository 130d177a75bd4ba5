#include "engine/deform.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numbers>
#include <sstream>

#include "engine/flat_locator.hpp"
#include "engine/parallel.hpp"

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
  }
  return m;
}

// Convex hull (Andrew's monotone chain), counter-clockwise. Points strictly
// inside the quadrilateral of the four axis-extreme points cannot be on the
// hull and are dropped first (Akl-Toussaint): for a scanned model that is
// nearly all of them, which saves most of the sort.
std::vector<Vec2> ConvexHull(const std::vector<Vec2>& points) {
  std::vector<Vec2> p;
  if (points.size() > 64) {
    Vec2 quad[4] = {points[0], points[0], points[0], points[0]};  // min x, min y, max x, max y
    for (const Vec2& q : points) {
      if (q.x() < quad[0].x()) quad[0] = q;
      if (q.y() < quad[1].y()) quad[1] = q;
      if (q.x() > quad[2].x()) quad[2] = q;
      if (q.y() > quad[3].y()) quad[3] = q;
    }
    auto strictly_inside = [&quad](const Vec2& q) {
      for (int k = 0; k < 4; ++k) {  // counter-clockwise quadrilateral
        const Vec2 e = quad[(k + 1) % 4] - quad[k];
        const Vec2 r = q - quad[k];
        if (e.x() * r.y() - e.y() * r.x() <= 0.0) return false;
      }
      return true;
    };
    for (const Vec2& q : points) {
      if (!strictly_inside(q)) p.push_back(q);
    }
  } else {
    p = points;
  }
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

struct Placement {
  Mat3 basis;       // model -> (a, b, h) directions
  Vec2 centre;      // footprint centre, in (a, b) before the transform
  double h0 = 0.0;  // model height that lands on the surface
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  double scale = 1.0;
  Vec2 target = Vec2::Zero();  // where the centre goes on the sheet

  Vec3 Apply(const Vec3& p) const {
    const Vec3 q = basis * p;
    const Vec2 ab = target + scale * (rotation * (q.head<2>() - centre));
    return Vec3(ab.x(), ab.y(), scale * (q.z() - h0));
  }
  // The linear part of Apply.
  Mat3 Linear() const {
    Mat3 r = Mat3::Identity();
    r.topLeftCorner<2, 2>() = rotation;
    return scale * r * basis;
  }
};

std::string Num(double x) {
  std::ostringstream os;
  os.precision(6);
  os << x;
  return os.str();
}

// The largest scale at which the footprint, outlined by its convex hull, stays
// inside the sheet at least `margin` from its boundary. The sheet is simply
// connected, so a hull outline inside it encloses only sheet points.
Result<double> FitScale(const FlatLocator& locator, const std::vector<Vec2>& footprint,
                        const Placement& base, double margin) {
  std::vector<Vec2> hull = ConvexHull(footprint);
  double extent = 0.0;
  for (const Vec2& p : hull) extent = std::max(extent, (p - base.centre).norm());
  if (!(extent > 0.0)) {
    return Degenerate("the model's footprint is a single point: nothing to fit", "placement.scale");
  }
  // Outline samples at most `spacing` apart: when every sample is inside the
  // sheet and at least `margin` from its boundary, every point of the outline
  // is at least margin - spacing / 2 > 0 from it, so the outline is inside.
  const Eigen::AlignedBox2d& sheet_box = locator.bounds();
  const double spacing =
      margin > 0.0 ? margin : 0.01 * sheet_box.sizes().minCoeff();  // no margin: 1% of the sheet
  auto inside_at = [&](double s) {
    int hint = -1;
    for (size_t k = 0; k < hull.size(); ++k) {
      const Vec2 a = base.target + s * (base.rotation * (hull[k] - base.centre));
      const Vec2 b =
          base.target + s * (base.rotation * (hull[(k + 1) % hull.size()] - base.centre));
      const int steps = std::clamp(static_cast<int>(std::ceil((b - a).norm() / spacing)), 1, 4096);
      for (int q = 0; q < steps; ++q) {
        const Vec2 placed = a + (b - a) * (static_cast<double>(q) / steps);
        SheetLocation l;
        if (!locator.Locate(placed, &l, &hint)) return false;
        if (locator.BoundaryWithin(placed, margin)) return false;
      }
    }
    return true;
  };
  if (!inside_at(0.0)) {
    return Status(ErrorCode::kOutsideSheet,
                  "the footprint's centre is not inside the flat sheet (with the margin), so no "
                  "scale fits; move placement.center",
                  "placement.center");
  }
  double lo = 0.0;
  double hi = locator.bounds().diagonal().norm() / extent;
  // To a relative 1e-5: far below the margin's own precision.
  for (int it = 0; it < 60 && hi - lo > 1e-5 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (inside_at(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

Status ValidatePlacement(const PlacementOptions& o) {
  if (!std::isfinite(o.anchor_value)) {
    return InvalidArgument("must be a finite number", "placement.anchor");
  }
  if (!o.center.allFinite()) return InvalidArgument("must be finite", "placement.center");
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
  if (o.threads < 0 || o.threads > 256) {
    return InvalidArgument("must be from 0 to 256", "placement.threads");
  }
  return Status::Ok();
}

namespace {

// The deformation of `mesh` into `*result`. result->mesh is either empty
// (then everything but the attributes that are recomputed is copied from
// `mesh`) or `mesh` itself (in place: each vertex reads only its own input
// before writing its output).
Status Deform(const Surface& surface, const FlatSheet& sheet, const Mesh& mesh,
              const PlacementOptions& o, DeformResult* result_out) {
  const auto t0 = std::chrono::steady_clock::now();
  SURFDEFORM_RETURN_IF_ERROR(ValidatePlacement(o));
  if (const std::string problem = CheckMesh(mesh); !problem.empty()) {
    return InvalidArgument("malformed mesh: " + problem, "mesh");
  }
  if (sheet.nu < 2 || sheet.nv < 2 ||
      sheet.flat.size() != static_cast<size_t>(sheet.nu) * sheet.nv) {
    return InvalidArgument("the flat sheet is empty or inconsistent", "surface");
  }
  const size_t n = mesh.positions.size();
  for (size_t k = 0; k < n; ++k) {
    if (!mesh.positions[k].allFinite()) {
      return InvalidArgument("vertex position is not finite",
                             "mesh.positions[" + std::to_string(k) + "]");
    }
  }

  // Placement.
  Placement pl;
  pl.basis = AxisBasis(o.up);
  Eigen::AlignedBox3d box;
  std::vector<Vec2> footprint(n);
  for (size_t k = 0; k < n; ++k) {
    const Vec3 q = pl.basis * mesh.positions[k];
    box.extend(q);
    footprint[k] = q.head<2>();
  }
  if (n == 0) box.extend(Vec3::Zero());
  pl.centre = 0.5 * (box.min().head<2>() + box.max().head<2>());
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
    case AnchorMode::kValue:
      pl.h0 = o.anchor_value;
      break;
  }
  const double angle = o.rotation_deg * std::numbers::pi / 180.0;
  pl.rotation << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  FlatLocator locator(sheet);
  const Eigen::AlignedBox2d& sb = locator.bounds();
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
      pl.target = locator.FlatPoint(mid);
      break;
    }
    case CenterMode::kSheetUnits:
      pl.target = o.center;
      break;
    case CenterMode::kFraction:
      pl.target = sb.min() + o.center.cwiseProduct(sb.sizes());
      break;
  }
  pl.scale = o.scale;
  if (o.fit) {
    auto s = FitScale(locator, footprint, pl, o.fit_margin * sb.sizes().minCoeff());
    if (!s.ok()) return s.status();
    pl.scale = *s;
  }
  const Mat3 linear = pl.Linear();
  const Mat3 normal_linear = linear.inverse().transpose();

  // Deformation, vertex by vertex.
  DeformResult& result = *result_out;
  Mesh& out = result.mesh;
  if (&out != &mesh) {
    // Attributes, triangles and groups carry over; positions, normals and
    // tangents are all written below, so they are only sized, not copied.
    out.triangles = mesh.triangles;
    out.groups = mesh.groups;
    out.uv0 = mesh.uv0;
    out.uv1 = mesh.uv1;
    out.colors = mesh.colors;
    out.positions.resize(n);
    out.normals.resize(mesh.normals.size());
    out.tangents.resize(mesh.tangents.size());
  }
  const bool need_frame = !mesh.normals.empty() || !mesh.tangents.empty();
  const Vec2 param_scale = locator.ParameterScale();
  const bool exact = sheet.method == "exact" && surface.InverseUnrolling(Vec2(1, 1)).has_value();
  const Eigen::Matrix2d raw_from_sheet = sheet.frame_linear.inverse();
  const double sheet_size = sb.diagonal().norm();
  const int threads = n >= 4096 ? ResolveThreads(o.threads) : 1;
  std::vector<size_t> outside(threads, 0);
  std::vector<double> worst(threads, 0.0);
  std::vector<long long> bad(threads, -1);  // first vertex with a non-finite result
  ParallelChunks(static_cast<int>(n), threads, [&](int chunk, int begin, int end) {
    int hint = -1;  // the previous vertex's cell
    for (int k = begin; k < end; ++k) {
      const Vec3 placed = pl.Apply(mesh.positions[k]);
      const Vec2 ab = placed.head<2>();
      const double h = placed.z();
      Vec2 uv;
      Eigen::Matrix2d duv;  // d(u, v)/d(a, b)
      if (exact) {
        // Developable kinds: invert the closed-form unrolling (exact, where the
        // cell-wise bilinear map is only second-order accurate on a cone).
        auto inverse = [&](const Vec2& p) {
          return *surface.InverseUnrolling(raw_from_sheet * (p - sheet.frame_offset));
        };
        uv = inverse(ab);
        constexpr double kIn = 1e-9;
        if (!(uv.x() >= -kIn && uv.x() <= 1 + kIn && uv.y() >= -kIn && uv.y() <= 1 + kIn)) {
          double distance;
          locator.NearestOnBoundary(ab, &distance);
          ++outside[chunk];
          worst[chunk] = std::max(worst[chunk], distance);
          if (o.outside == OutsideMode::kError) continue;
          if (o.outside == OutsideMode::kClamp) uv = uv.cwiseMax(0.0).cwiseMin(1.0);
        }
        if (need_frame) {
          const double step = 1e-6 * sheet_size;
          duv.col(0) = (inverse(ab + Vec2(step, 0)) - inverse(ab - Vec2(step, 0))) / (2 * step);
          duv.col(1) = (inverse(ab + Vec2(0, step)) - inverse(ab - Vec2(0, step))) / (2 * step);
        }
      } else {
        SheetLocation loc;
        if (!locator.Locate(ab, &loc, &hint)) {
          double distance;
          loc = locator.NearestOnBoundary(ab, &distance);
          ++outside[chunk];
          worst[chunk] = std::max(worst[chunk], distance);
          if (o.outside == OutsideMode::kError) continue;
          if (o.outside == OutsideMode::kExtrapolate) {
            // Continue the boundary cell's map: d(s, t) = J^-1 (p - q).
            const Vec2 q = locator.FlatPoint(loc);
            const Vec2 d = locator.FlatJacobian(loc).inverse() * (ab - q);
            loc.s += d.x();
            loc.t += d.y();
          }
        }
        uv = locator.Parameters(loc);
        if (need_frame) duv = param_scale.asDiagonal() * locator.FlatJacobian(loc).inverse();
      }
      const SurfacePoint s = surface.Evaluate(uv.x(), uv.y(), need_frame ? 2 : 1);
      const Vec3 cross = s.su.cross(s.sv);
      const double cross_len = cross.norm();
      const Vec3 nrm = cross / cross_len;
      out.positions[k] = s.p + h * nrm;
      if (need_frame) {
        // Derivatives of the unit normal (Weingarten): N_x = (n_x - N (N . n_x)) / |n|.
        const Vec3 nu_raw = s.suu.cross(s.sv) + s.su.cross(s.suv);
        const Vec3 nv_raw = s.suv.cross(s.sv) + s.su.cross(s.svv);
        const Vec3 n_u = (nu_raw - nrm * nrm.dot(nu_raw)) / cross_len;
        const Vec3 n_v = (nv_raw - nrm * nrm.dot(nv_raw)) / cross_len;
        const Vec3 fu = s.su + h * n_u;
        const Vec3 fv = s.sv + h * n_v;
        Mat3 jac;  // d(position)/d(a, b, h)
        jac.col(0) = fu * duv(0, 0) + fv * duv(1, 0);
        jac.col(1) = fu * duv(0, 1) + fv * duv(1, 1);
        jac.col(2) = nrm;
        const Mat3 total = jac * linear;
        if (!mesh.normals.empty()) {
          // J^-T n up to a positive factor (1 / det J), which the normalisation
          // removes: the cofactor matrix, i.e. cross products of J's columns.
          const Vec3 m = normal_linear * mesh.normals[k];
          const Vec3 nn = m.x() * jac.col(1).cross(jac.col(2)) +
                          m.y() * jac.col(2).cross(jac.col(0)) +
                          m.z() * jac.col(0).cross(jac.col(1));
          out.normals[k] = nn.normalized();
        }
        if (!mesh.tangents.empty()) {
          const Vec4& t = mesh.tangents[k];
          const Vec3 tt = (total * t.head<3>()).normalized();
          const double w = total.determinant() < 0.0 ? -t.w() : t.w();
          out.tangents[k] = Vec4(tt.x(), tt.y(), tt.z(), w);
        }
      }
      const bool finite = out.positions[k].allFinite() &&
                          (mesh.normals.empty() || out.normals[k].allFinite()) &&
                          (mesh.tangents.empty() || out.tangents[k].allFinite());
      if (!finite && bad[chunk] < 0) bad[chunk] = k;
    }
  });
  DeformStats& st = result.stats;
  st.vertices = n;
  st.triangles = mesh.triangles.size();
  st.scale = pl.scale;
  for (int c = 0; c < threads; ++c) {
    st.outside += outside[c];
    st.max_outside_distance = std::max(st.max_outside_distance, worst[c]);
  }
  if (st.outside > 0 && o.outside == OutsideMode::kError) {
    return Status(ErrorCode::kOutsideSheet,
                  std::to_string(st.outside) + " of " + std::to_string(n) +
                      " vertices fall outside the flat sheet, the farthest " +
                      Num(st.max_outside_distance) +
                      " sheet units away; scale the model down, move it (placement.center), use "
                      "placement.scale \"fit\", or set placement.outside to \"clamp\" or "
                      "\"extrapolate\"",
                  "placement");
  }
  for (int c = 0; c < threads; ++c) {
    if (bad[c] >= 0) {
      return Degenerate("the deformation of vertex " + std::to_string(bad[c]) +
                            " is not finite (the surface normal vanishes there)",
                        "surface");
    }
  }
  st.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return Status::Ok();
}

}  // namespace

Result<DeformResult> DeformMesh(const Surface& surface, const FlatSheet& sheet, const Mesh& mesh,
                                const PlacementOptions& options) {
  DeformResult result;
  SURFDEFORM_RETURN_IF_ERROR(Deform(surface, sheet, mesh, options, &result));
  return result;
}

Result<DeformResult> DeformMesh(const Surface& surface, const FlatSheet& sheet, Mesh&& mesh,
                                const PlacementOptions& options) {
  DeformResult result;
  result.mesh = std::move(mesh);
  SURFDEFORM_RETURN_IF_ERROR(Deform(surface, sheet, result.mesh, options, &result));
  return result;
}

}  // namespace surfdeform
