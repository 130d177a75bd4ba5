#include "engine/flatten/seam_extension.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace surfdeform {
namespace {

double Wrap(double u) { return u - std::floor(u); }

// The given surface over the extended columns and rows: (u', v') in
// [0, 1]^2 is the given (u0 + u_scale u', v0 + v_scale v'), evaluated there
// wrapped into [0, 1) in the directions where the surface closes. Its
// closed-form unrolling is the given one continued (not wrapped): the
// extended sheet.
class AcrossSeam final : public Surface {
 public:
  AcrossSeam(const Surface& given, double u0, double u_scale, double v0, double v_scale)
      : given_(given),
        u0_(u0),
        su_(u_scale),
        v0_(v0),
        sv_(v_scale),
        wrap_u_(given.ClosedInU()),
        wrap_v_(given.ClosedInV()) {}

  const char* Kind() const override { return given_.Kind(); }

  SurfacePoint Evaluate(double u, double v, int order) const override {
    const double gu = u0_ + su_ * u, gv = v0_ + sv_ * v;
    SurfacePoint s = given_.Evaluate(wrap_u_ ? Wrap(gu) : gu, wrap_v_ ? Wrap(gv) : gv, order);
    s.su *= su_;
    s.sv *= sv_;
    s.suu *= su_ * su_;
    s.suv *= su_ * sv_;
    s.svv *= sv_ * sv_;
    return s;
  }

  std::optional<Vec2> ExactUnrolling(double u, double v) const override {
    return given_.ExactUnrolling(u0_ + su_ * u, v0_ + sv_ * v);
  }

  std::optional<Vec2> InverseUnrolling(const Vec2& flat) const override {
    const std::optional<Vec2> g = given_.InverseUnrolling(flat);
    if (!g) return std::nullopt;
    return Vec2((g->x() - u0_) / su_, (g->y() - v0_) / sv_);
  }

  bool ClosedInU() const override { return false; }  // continued, not closed

 private:
  const Surface& given_;
  const double u0_, su_, v0_, sv_;
  const bool wrap_u_, wrap_v_;
};

// Whether the closed-form unrolling of u in [-e / P, 1 + e / P] inverts back
// to u at every column: the continued sheet does not meet itself in the
// plane (a cone's sector, continued past half a turn from its middle,
// would).
bool Invertible(const Surface& s, int e, int period, int nv) {
  for (int i = -e; i <= period + e; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = static_cast<double>(i) / period;
      const double v = static_cast<double>(j) / (nv - 1);
      const std::optional<Vec2> flat = s.ExactUnrolling(u, v);
      if (!flat) return false;
      const std::optional<Vec2> back = s.InverseUnrolling(*flat);
      if (!back || !(std::abs(back->x() - u) <= 1e-9)) return false;
    }
  }
  return true;
}

bool Unrolled(const Surface& surface, const FlatSheet& sheet) {
  return sheet.method == "exact" && surface.InverseUnrolling(Vec2(1, 1)).has_value();
}

bool Flattened(const FlatSheet& sheet) { return !sheet.period_u.isZero(); }

}  // namespace

std::unique_ptr<const Surface> Continued(const Surface& given, double u0, double u_scale, double v0,
                                         double v_scale) {
  return std::make_unique<AcrossSeam>(given, u0, u_scale, v0, v_scale);
}

bool PeriodicInU(const Surface& surface, const FlatSheet& sheet) {
  return surface.ClosedInU() && sheet.nu >= 2 && sheet.nv >= 2 &&
         sheet.flat.size() == static_cast<size_t>(sheet.nu) * sheet.nv &&
         (Flattened(sheet) || Unrolled(surface, sheet));
}

std::optional<SheetPeriod> PeriodOf(const Surface& surface, const FlatSheet& sheet) {
  if (!PeriodicInU(surface, sheet)) return std::nullopt;
  if (Flattened(sheet)) return SheetPeriod{0.0, sheet.period_u};
  // The rotation and translation that best take column 0 onto column nu - 1
  // (Kabsch in the plane); exact up to rounding for a closed-form sheet.
  const int nu = sheet.nu, nv = sheet.nv;
  Vec2 ca = Vec2::Zero(), cb = Vec2::Zero();
  for (int j = 0; j < nv; ++j) {
    ca += sheet.flat[static_cast<size_t>(nu) * j];
    cb += sheet.flat[static_cast<size_t>(nu) * j + nu - 1];
  }
  ca /= nv;
  cb /= nv;
  double dot = 0.0, cross = 0.0;
  for (int j = 0; j < nv; ++j) {
    const Vec2 a = sheet.flat[static_cast<size_t>(nu) * j] - ca;
    const Vec2 b = sheet.flat[static_cast<size_t>(nu) * j + nu - 1] - cb;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  SheetPeriod p;
  p.angle = std::atan2(cross, dot);
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(p.angle).toRotationMatrix();
  p.translation = cb - r * ca;
  return p;
}

Vec2 SeamExtension::GivenParameters(const Vec2& extended) const {
  const double u = u0 + u_scale * extended.x(), v = v0 + v_scale * extended.y();
  return Vec2(period_columns > 0 ? Wrap(u) : u, period_rows > 0 ? Wrap(v) : v);
}

Vec2 SeamExtension::ExtendedParameters(const Vec2& given) const {
  return Vec2((given.x() - u0) / u_scale, (given.y() - v0) / v_scale);
}

bool PeriodicInV(const Surface& surface, const FlatSheet& sheet) {
  return surface.ClosedInV() && sheet.nu >= 2 && sheet.nv >= 2 &&
         sheet.flat.size() == static_cast<size_t>(sheet.nu) * sheet.nv && !sheet.period_v.isZero();
}

int SeamRows(const Surface& surface, const FlatSheet& sheet) {
  return PeriodicInV(surface, sheet) ? sheet.nv - 1 : 0;
}

int SeamColumns(const Surface& surface, const FlatSheet& sheet) {
  if (!PeriodicInU(surface, sheet)) return 0;
  const int period = sheet.nu - 1;
  int e = period;                  // a period each side, where the plane allows
  if (Flattened(sheet)) return e;  // translated copies of a strip never meet
  while (e > 0 && !Invertible(surface, e, period, sheet.nv)) e /= 2;
  return e;
}

std::unique_ptr<const SeamExtension> ExtendAcrossSeam(const Surface& surface,
                                                      const FlatSheet& sheet, int columns) {
  const int most = SeamColumns(surface, sheet);
  const int eu = columns < 0 ? most : std::min(columns, most);
  const int ev = SeamRows(surface, sheet);
  if (eu <= 0 && ev <= 0) return nullptr;
  const int pu = sheet.nu - 1, pv = sheet.nv - 1;
  auto x = std::make_unique<SeamExtension>();
  x->columns = eu;
  x->rows = ev;
  x->period_columns = eu > 0 ? pu : 0;
  x->period_rows = ev > 0 ? pv : 0;
  FlatSheet& s = x->sheet;
  s.nu = sheet.nu + 2 * eu;
  s.nv = sheet.nv + 2 * ev;
  x->u0 = -static_cast<double>(eu) / pu;
  x->u_scale = static_cast<double>(s.nu - 1) / pu;
  x->v0 = -static_cast<double>(ev) / pv;
  x->v_scale = static_cast<double>(s.nv - 1) / pv;
  x->surface = std::make_unique<AcrossSeam>(surface, x->u0, x->u_scale, x->v0, x->v_scale);
  s.method = sheet.method;
  s.frame_linear = sheet.frame_linear;
  s.frame_offset = sheet.frame_offset;
  s.period_u = sheet.period_u;
  s.period_v = sheet.period_v;
  s.quality = sheet.quality;
  const size_t n = static_cast<size_t>(s.nu) * s.nv;
  s.points.resize(n);
  s.normals.resize(n);
  s.flat.resize(n);
  const bool samples =
      sheet.points.size() == sheet.flat.size() && sheet.normals.size() == sheet.flat.size();
  auto floor_div = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  for (int j = 0; j < s.nv; ++j) {
    for (int i = 0; i < s.nu; ++i) {
      const size_t k = static_cast<size_t>(i) + static_cast<size_t>(s.nu) * j;
      const int gi = i - eu, gj = j - ev;
      const bool inside = gi >= 0 && gi < sheet.nu && gj >= 0 && gj < sheet.nv;
      if (inside || !sheet.period_u.isZero() || !sheet.period_v.isZero()) {
        // The given samples as they are; past a seam, the sample a period
        // away, its flat point translated by the periods.
        const int ku = gi >= 0 && gi < sheet.nu ? 0 : floor_div(gi, pu);
        const int kv = gj >= 0 && gj < sheet.nv ? 0 : floor_div(gj, pv);
        const size_t g =
            static_cast<size_t>(gi - ku * pu) + static_cast<size_t>(sheet.nu) * (gj - kv * pv);
        s.flat[k] = sheet.flat[g] + ku * sheet.period_u + kv * sheet.period_v;
        s.points[k] = samples ? sheet.points[g] : Vec3::Zero();
        s.normals[k] = samples ? sheet.normals[g] : Vec3::Zero();
        continue;
      }
      // A closed-form sheet (periodic in u only): continued by its unrolling.
      const double u = static_cast<double>(gi) / pu;
      const double v = static_cast<double>(gj) / pv;
      s.flat[k] = sheet.frame_linear * *surface.ExactUnrolling(u, v) + sheet.frame_offset;
      const SurfacePoint p = surface.Evaluate(Wrap(u), v, 1);
      s.points[k] = p.p;
      s.normals[k] = UnitNormal(p);
    }
  }
  return x;
}

}  // namespace surfdeform
