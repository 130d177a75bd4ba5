#include "engine/surface/analytic_surfaces.hpp"

#include <cmath>
#include <numbers>

namespace surfdeform {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// Applies the frame to a point evaluated in local coordinates.
SurfacePoint ToWorld(const RigidFrame& f, const SurfacePoint& l) {
  SurfacePoint w;
  const Eigen::Matrix3d& r = f.rotation;
  w.p = f.origin + r * l.p;
  w.su = r * l.su;
  w.sv = r * l.sv;
  w.suu = r * l.suu;
  w.suv = r * l.suv;
  w.svv = r * l.svv;
  return w;
}

// Surface of revolution about +Z with radius rho(v) and height z(v), both
// linear in v, over the angle theta = angle0 + u * span. Cylinder and cone.
class RuledRevolution final : public Surface {
 public:
  RuledRevolution(const char* kind, double r0, double r1, double height, double span,
                  const RigidFrame& frame)
      : kind_(kind), r0_(r0), r1_(r1), h_(height), span_(span), frame_(frame) {}

  const char* Kind() const override { return kind_; }

  // A whole turn: the angle u * span goes round.
  bool ClosedInU() const override { return span_ >= 2.0 * std::numbers::pi * (1.0 - 1e-12); }

  SurfacePoint Evaluate(double u, double v, int order) const override {
    const double theta = u * span_;
    const double c = std::cos(theta);
    const double s = std::sin(theta);
    const double rho = r0_ + (r1_ - r0_) * v;
    const double dr = r1_ - r0_;
    SurfacePoint l;
    l.p = Vec3(rho * c, rho * s, h_ * v);
    if (order >= 1) {
      l.su = Vec3(-s, c, 0.0) * (span_ * rho);
      l.sv = Vec3(dr * c, dr * s, h_);
    }
    if (order >= 2) {
      l.suu = Vec3(c, s, 0.0) * (-span_ * span_ * rho);
      l.suv = Vec3(-s, c, 0.0) * (span_ * dr);
    }
    return ToWorld(frame_, l);
  }

  // Unrolls the patch into the plane: for a cylinder a rectangle of size
  // (radius * span) x height; for a cone an annular sector around the apex.
  std::optional<Vec2> ExactUnrolling(double u, double v) const override {
    const double dr = r1_ - r0_;
    if (dr == 0.0) return Vec2(r0_ * span_ * u, h_ * v);
    const double slant = std::hypot(h_, dr);
    const double v_apex = -r0_ / dr;
    const double dist = std::abs(v - v_apex) * slant;  // distance from the apex
    const double phi = u * span_ * std::abs(dr) / slant;
    return Vec2(dist * std::cos(phi), dist * std::sin(phi));
  }

  std::optional<Vec2> InverseUnrolling(const Vec2& flat) const override {
    const double dr = r1_ - r0_;
    if (dr == 0.0) return Vec2(flat.x() / (r0_ * span_), flat.y() / h_);
    const double slant = std::hypot(h_, dr);
    const double sector = span_ * std::abs(dr) / slant;  // unrolled angle, < 2 pi
    // The angle measured from the sector's middle: continuous over the sector
    // and past it up to half a turn from the middle (unrolled sectors are less
    // than a full turn wide).
    const double mid = 0.5 * sector;
    const Vec2 m(std::cos(mid), std::sin(mid));
    const double phi = mid + std::atan2(m.x() * flat.y() - m.y() * flat.x(), m.dot(flat));
    const double dist = flat.norm();
    const double v_apex = -r0_ / dr;
    const double v = dr > 0.0 ? v_apex + dist / slant : v_apex - dist / slant;
    return Vec2(phi / sector, v);
  }

 private:
  const char* kind_;
  double r0_, r1_, h_, span_;
  RigidFrame frame_;
};

// Sphere (tube radius = 0 about the centre) and torus: the point at angle
// theta around +Z and angle phi up from the equator of a circle of radius
// `minor` whose centre runs on a circle of radius `major`.
class RevolvedCircle final : public Surface {
 public:
  RevolvedCircle(const char* kind, double major, double minor, double theta0, double theta_span,
                 double phi0, double phi_span, const RigidFrame& frame)
      : kind_(kind),
        major_(major),
        minor_(minor),
        t0_(theta0),
        dt_(theta_span),
        p0_(phi0),
        dp_(phi_span),
        frame_(frame) {}

  const char* Kind() const override { return kind_; }

  SurfacePoint Evaluate(double u, double v, int order) const override {
    const double theta = t0_ + u * dt_;
    const double phi = p0_ + v * dp_;
    const double ct = std::cos(theta), st = std::sin(theta);
    const double cp = std::cos(phi), sp = std::sin(phi);
    const double rho = major_ + minor_ * cp;
    const Vec3 radial(ct, st, 0.0);
    const Vec3 tangential(-st, ct, 0.0);
    const Vec3 tube_out(cp * ct, cp * st, sp);   // unit vector away from the tube centre
    const Vec3 tube_up(-sp * ct, -sp * st, cp);  // d(tube_out)/dphi
    SurfacePoint l;
    l.p = rho * radial + Vec3(0.0, 0.0, minor_ * sp);
    if (order >= 1) {
      l.su = tangential * (dt_ * rho);
      l.sv = tube_up * (dp_ * minor_);
    }
    if (order >= 2) {
      l.suu = radial * (-dt_ * dt_ * rho);
      l.suv = tangential * (-dt_ * dp_ * minor_ * sp);
      l.svv = tube_out * (-dp_ * dp_ * minor_);
    }
    return ToWorld(frame_, l);
  }

  // A sphere's whole longitude, a torus whole round its axis.
  bool ClosedInU() const override { return dt_ >= 2.0 * std::numbers::pi * (1.0 - 1e-12); }
  // A torus all round its tube.
  bool ClosedInV() const override { return dp_ >= 2.0 * std::numbers::pi * (1.0 - 1e-12); }

 private:
  const char* kind_;
  double major_, minor_, t0_, dt_, p0_, dp_;
  RigidFrame frame_;
};

class WaveSurface final : public Surface {
 public:
  WaveSurface(const WaveSpec& spec, const RigidFrame& frame) : s_(spec), frame_(frame) {
    k_ = 2.0 * std::numbers::pi / spec.wavelength;
  }

  const char* Kind() const override { return "wave"; }

  SurfacePoint Evaluate(double u, double v, int order) const override {
    const double x = u * s_.length;
    const double phase = k_ * (x - s_.speed * s_.time);
    const double a = s_.amplitude;
    const double lk = s_.length * k_;
    SurfacePoint l;
    l.p = Vec3(x, v * s_.width, a * std::sin(phase));
    if (order >= 1) {
      l.su = Vec3(s_.length, 0.0, a * lk * std::cos(phase));
      l.sv = Vec3(0.0, s_.width, 0.0);
    }
    if (order >= 2) l.suu = Vec3(0.0, 0.0, -a * lk * lk * std::sin(phase));
    return ToWorld(frame_, l);
  }

 private:
  WaveSpec s_;
  RigidFrame frame_;
  double k_ = 1.0;
};

}  // namespace

std::unique_ptr<Surface> MakeCylinder(const CylinderSpec& s, const RigidFrame& f) {
  return std::make_unique<RuledRevolution>("cylinder", s.radius, s.radius, s.height,
                                           s.angle_deg * kDegToRad, f);
}

std::unique_ptr<Surface> MakeCone(const ConeSpec& s, const RigidFrame& f) {
  return std::make_unique<RuledRevolution>("cone", s.radius_bottom, s.radius_top, s.height,
                                           s.angle_deg * kDegToRad, f);
}

std::unique_ptr<Surface> MakeSphere(const SphereSpec& s, const RigidFrame& f) {
  return std::make_unique<RevolvedCircle>("sphere", 0.0, s.radius, s.lon_min_deg * kDegToRad,
                                          (s.lon_max_deg - s.lon_min_deg) * kDegToRad,
                                          s.lat_min_deg * kDegToRad,
                                          (s.lat_max_deg - s.lat_min_deg) * kDegToRad, f);
}

std::unique_ptr<Surface> MakeTorus(const TorusSpec& s, const RigidFrame& f) {
  return std::make_unique<RevolvedCircle>(
      "torus", s.major_radius, s.minor_radius, s.u_min_deg * kDegToRad,
      (s.u_max_deg - s.u_min_deg) * kDegToRad, s.v_min_deg * kDegToRad,
      (s.v_max_deg - s.v_min_deg) * kDegToRad, f);
}

std::unique_ptr<Surface> MakeWave(const WaveSpec& s, const RigidFrame& f) {
  return std::make_unique<WaveSurface>(s, f);
}

}  // namespace surfdeform
