#include "engine/seam_extension.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace surfdeform {
namespace {

double Wrap(double u) { return u - std::floor(u); }

// The given surface over the extended columns: u' in [0, 1] is the given
// u0 + u_scale u', evaluated at that u wrapped into [0, 1). Its closed-form
// unrolling is the given one continued (not wrapped): the extended sheet.
class AcrossSeam final : public Surface {
 public:
  AcrossSeam(const Surface& given, double u0, double u_scale)
      : given_(given), u0_(u0), scale_(u_scale) {}

  const char* Kind() const override { return given_.Kind(); }

  SurfacePoint Evaluate(double u, double v, int order) const override {
    SurfacePoint s = given_.Evaluate(Wrap(u0_ + scale_ * u), v, order);
    s.su *= scale_;
    s.suu *= scale_ * scale_;
    s.suv *= scale_;
    return s;
  }

  std::optional<Vec2> ExactUnrolling(double u, double v) const override {
    return given_.ExactUnrolling(u0_ + scale_ * u, v);
  }

  std::optional<Vec2> InverseUnrolling(const Vec2& flat) const override {
    const std::optional<Vec2> g = given_.InverseUnrolling(flat);
    if (!g) return std::nullopt;
    return Vec2((g->x() - u0_) / scale_, g->y());
  }

 private:
  const Surface& given_;
  const double u0_, scale_;
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

std::unique_ptr<const Surface> ContinuedInU(const Surface& given, double u0, double u_scale) {
  return std::make_unique<AcrossSeam>(given, u0, u_scale);
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
  return Vec2(Wrap(u0 + u_scale * extended.x()), extended.y());
}

Vec2 SeamExtension::ExtendedParameters(const Vec2& given) const {
  return Vec2((given.x() - u0) / u_scale, given.y());
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
  const int e = columns < 0 ? most : std::min(columns, most);
  if (e <= 0) return nullptr;
  const int period = sheet.nu - 1, nv = sheet.nv;
  auto x = std::make_unique<SeamExtension>();
  x->columns = e;
  x->period_columns = period;
  FlatSheet& s = x->sheet;
  s.nu = sheet.nu + 2 * e;
  s.nv = nv;
  x->u0 = -static_cast<double>(e) / period;
  x->u_scale = static_cast<double>(s.nu - 1) / period;
  x->surface = std::make_unique<AcrossSeam>(surface, x->u0, x->u_scale);
  s.method = sheet.method;
  s.frame_linear = sheet.frame_linear;
  s.frame_offset = sheet.frame_offset;
  s.period_u = sheet.period_u;
  s.quality = sheet.quality;
  const size_t n = static_cast<size_t>(s.nu) * nv;
  s.points.resize(n);
  s.normals.resize(n);
  s.flat.resize(n);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < s.nu; ++i) {
      const size_t k = static_cast<size_t>(i) + static_cast<size_t>(s.nu) * j;
      const int given = i - e;
      if (given >= 0 && given < sheet.nu) {  // the given columns, as they are
        const size_t g = static_cast<size_t>(given) + static_cast<size_t>(sheet.nu) * j;
        s.flat[k] = sheet.flat[g];
        s.points[k] = sheet.points.size() == sheet.flat.size() ? sheet.points[g] : Vec3::Zero();
        s.normals[k] = sheet.normals.size() == sheet.flat.size() ? sheet.normals[g] : Vec3::Zero();
        continue;
      }
      if (Flattened(sheet)) {  // the column a period away, translated
        const int turns = given < 0 ? -1 : given / period;
        const size_t g =
            static_cast<size_t>(given - turns * period) + static_cast<size_t>(sheet.nu) * j;
        s.flat[k] = sheet.flat[g] + turns * sheet.period_u;
        s.points[k] = sheet.points.size() == sheet.flat.size() ? sheet.points[g] : Vec3::Zero();
        s.normals[k] = sheet.normals.size() == sheet.flat.size() ? sheet.normals[g] : Vec3::Zero();
        continue;
      }
      const double u = static_cast<double>(given) / period;
      const double v = static_cast<double>(j) / (nv - 1);
      s.flat[k] = sheet.frame_linear * *surface.ExactUnrolling(u, v) + sheet.frame_offset;
      const SurfacePoint p = surface.Evaluate(Wrap(u), v, 1);
      s.points[k] = p.p;
      s.normals[k] = UnitNormal(p);
    }
  }
  return x;
}

}  // namespace surfdeform
