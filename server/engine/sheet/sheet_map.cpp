#include "engine/sheet/sheet_map.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/common/clamped_floor.hpp"

namespace surfdeform {

SheetMap::SheetMap(const Surface& surface, const FlatSheet& sheet, int seam_columns)
    : extension_(seam_columns == 0 ? nullptr : ExtendAcrossSeam(surface, sheet, seam_columns)),
      given_sheet_(sheet),
      surface_(extension_ ? *extension_->surface : surface),
      sheet_(extension_ ? extension_->sheet : sheet),
      locator_(sheet_),
      given_locator_(extension_ ? std::make_shared<const FlatLocator>(sheet) : nullptr) {
  exact_ = (sheet_.method == "exact" || surface_.flat_mesh() != nullptr) &&
           surface_.InverseUnrolling(Vec2(1, 1)).has_value();
  raw_from_sheet_ = sheet_.frame_linear.inverse();
  sheet_size_ = locator_.bounds().diagonal().norm();
}

SheetParameters SheetMap::Parameters(const Vec2& ab, OutsideMode outside, bool want_jacobian,
                                     int* hint) const {
  SheetParameters r;
  if (exact_) {
    // Developable kinds: invert the closed-form unrolling (exact, where the
    // cell-wise bilinear map is only second-order accurate on a cone).
    auto inverse = [&](const Vec2& p) {
      return *surface_.InverseUnrolling(raw_from_sheet_ * (p - sheet_.frame_offset));
    };
    r.uv = inverse(ab);
    Vec2 nearest;
    if (const std::optional<double> gap = surface_.DomainGap(r.uv, &nearest)) {
      // A surface over part of the square (a mesh): off it is outside.
      if (*gap > 0.0) {
        r.outside = true;
        r.outside_distance = *gap;
        if (outside == OutsideMode::kClamp) r.uv = nearest;
      }
    } else if (constexpr double kIn = 1e-9; !(r.uv.x() >= -kIn && r.uv.x() <= 1 + kIn &&
                                              r.uv.y() >= -kIn && r.uv.y() <= 1 + kIn)) {
      r.outside = true;
      locator_.NearestOnBoundary(ab, &r.outside_distance);
      if (outside == OutsideMode::kClamp) r.uv = r.uv.cwiseMax(0.0).cwiseMin(1.0);
    }
    if (want_jacobian) {
      const double step = 1e-6 * sheet_size_;
      r.duv.col(0) = (inverse(ab + Vec2(step, 0)) - inverse(ab - Vec2(step, 0))) / (2 * step);
      r.duv.col(1) = (inverse(ab + Vec2(0, step)) - inverse(ab - Vec2(0, step))) / (2 * step);
    }
    return r;
  }
  SheetLocation loc;
  if (!locator_.Locate(ab, &loc, hint)) {
    loc = locator_.NearestOnBoundary(ab, &r.outside_distance);
    r.outside = true;
    if (outside == OutsideMode::kExtrapolate) {
      // Continue the boundary cell's map: d(s, t) = J^-1 (p - q).
      const Vec2 q = locator_.FlatPoint(loc);
      const Vec2 d = locator_.FlatJacobian(loc).inverse() * (ab - q);
      loc.s += d.x();
      loc.t += d.y();
    }
  }
  if (!r.outside) return ParametersAt(loc, want_jacobian);
  r.uv = locator_.Parameters(loc);
  if (want_jacobian) r.duv = ParameterJacobian(loc);
  return r;
}

std::optional<double> SheetMap::DomainDepth(const Vec2& ab) const {
  if (!exact_) return std::nullopt;
  return surface_.DomainDepth(
      *surface_.InverseUnrolling(raw_from_sheet_ * (ab - sheet_.frame_offset)));
}

SheetParameters SheetMap::ParametersAt(const SheetLocation& location, bool want_jacobian) const {
  SheetParameters r;
  r.cell = locator_.CellIndex(location);
  r.location = location;
  r.uv = locator_.Parameters(location);
  if (want_jacobian) r.duv = ParameterJacobian(location);
  return r;
}

Eigen::Matrix2d SheetMap::ParameterJacobian(const SheetLocation& l) const {
  return locator_.ParameterScale().asDiagonal() * locator_.FlatJacobian(l).inverse();
}

Vec2 SheetMap::SheetPoint(const Vec2& uv) const {
  if (exact_) {
    if (const auto raw = surface_.ExactUnrolling(uv.x(), uv.y())) {
      return sheet_.frame_linear * *raw + sheet_.frame_offset;
    }
  }
  const int nu = locator_.nu(), nv = locator_.nv();
  const double gu = uv.x() * (nu - 1), gv = uv.y() * (nv - 1);
  SheetLocation l;
  l.i = ClampedFloor(gu, 0, nu - 2);
  l.j = ClampedFloor(gv, 0, nv - 2);
  l.s = gu - l.i;
  l.t = gv - l.j;
  return locator_.FlatPoint(l);
}

void SheetMap::SurfaceAndNormal(const Vec2& ab, OutsideMode outside, int* hint, Vec3* point,
                                Vec3* normal) const {
  if (outside == OutsideMode::kError) outside = OutsideMode::kExtrapolate;
  const SheetParameters p = Parameters(ab, outside, false, hint);
  const SurfacePoint s = surface_.Evaluate(p.uv.x(), p.uv.y(), 1);
  *point = s.p;
  *normal = UnitNormal(s);
}

Vec3 SheetMap::Position(const Vec3& abh, OutsideMode outside, int* hint) const {
  Vec3 point, normal;
  SurfaceAndNormal(abh.head<2>(), outside, hint, &point, &normal);
  return point + abh.z() * normal;
}

Status OutsideSheetError(size_t count, size_t n, double worst) {
  std::ostringstream os;
  os.precision(6);
  os << count << " of " << n << " vertices fall outside the flat sheet, the farthest " << worst
     << " sheet units away; scale the model down, move it (placement.center), use "
        "placement.scale \"fit\", or set placement.outside to \"clamp\" or \"extrapolate\"";
  return Status(ErrorCode::kOutsideSheet, os.str(), "placement");
}

Eigen::Matrix3d DeformJacobian(const SurfacePoint& s, const SheetParameters& p, double h,
                               Vec3* unit_normal) {
  const Vec3 cross = s.su.cross(s.sv);
  const double cross_len = cross.norm();
  const Vec3 nrm = cross / cross_len;
  // Derivatives of the unit normal (Weingarten): N_x = (n_x - N (N . n_x)) / |n|.
  const Vec3 nu_raw = s.suu.cross(s.sv) + s.su.cross(s.suv);
  const Vec3 nv_raw = s.suv.cross(s.sv) + s.su.cross(s.svv);
  const Vec3 n_u = (nu_raw - nrm * nrm.dot(nu_raw)) / cross_len;
  const Vec3 n_v = (nv_raw - nrm * nrm.dot(nv_raw)) / cross_len;
  const Vec3 fu = s.su + h * n_u;
  const Vec3 fv = s.sv + h * n_v;
  Eigen::Matrix3d jac;
  jac.col(0) = fu * p.duv(0, 0) + fv * p.duv(1, 0);
  jac.col(1) = fu * p.duv(0, 1) + fv * p.duv(1, 1);
  jac.col(2) = nrm;
  *unit_normal = nrm;
  return jac;
}

}  // namespace surfdeform
