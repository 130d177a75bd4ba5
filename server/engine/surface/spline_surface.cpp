#include "engine/surface/spline_surface.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <span>
#include <utility>

#include "engine/surface/bspline_basis.hpp"

namespace surfdeform {
namespace {

// Four values at once: one AVX2 vector (two SSE2 vectors without AVX).
using Lanes = Eigen::Array4d;

// A bicubic Bezier patch (4 x 4 control points, u fastest) and its
// derivatives up to kOrder at four parameter points, lane by lane:
// d[0] = S, d[1] = Su, d[2] = Sv, d[3] = Suu, d[4] = Suv, d[5] = Svv, each
// by coordinate (unset beyond kOrder). The sums of CombineBicubic, lane by
// lane: the same values to rounding (FMA contraction may differ).
template <int kOrder>
void BicubicBezier4(const Vec3* cp, const Lanes& u, const Lanes& v, Lanes d[6][3]) {
  Lanes nu[3][4], nv[3][4];
  CubicBernsteinDerivatives(u, kOrder, nu);
  CubicBernsteinDerivatives(v, kOrder, nv);
  constexpr int kOutputs = kOrder == 0 ? 1 : kOrder == 1 ? 3 : 6;
  for (int o = 0; o < kOutputs; ++o)
    for (int c = 0; c < 3; ++c) d[o][c].setZero();
  for (int j = 0; j < 4; ++j) {
    const Vec3* row = cp + 4 * j;
    for (int c = 0; c < 3; ++c) {
      const Lanes r0 =
          nu[0][0] * row[0][c] + nu[0][1] * row[1][c] + nu[0][2] * row[2][c] + nu[0][3] * row[3][c];
      d[0][c] += nv[0][j] * r0;
      if constexpr (kOrder >= 1) {
        const Lanes r1 = nu[1][0] * row[0][c] + nu[1][1] * row[1][c] + nu[1][2] * row[2][c] +
                         nu[1][3] * row[3][c];
        d[1][c] += nv[0][j] * r1;
        d[2][c] += nv[1][j] * r0;
        if constexpr (kOrder >= 2) {
          const Lanes r2 = nu[2][0] * row[0][c] + nu[2][1] * row[1][c] + nu[2][2] * row[2][c] +
                           nu[2][3] * row[3][c];
          d[3][c] += nv[0][j] * r2;
          d[4][c] += nv[1][j] * r1;
          d[5][c] += nv[2][j] * r0;
        }
      }
    }
  }
}

template <typename V>
struct Derivs {
  V p = V::Zero(), su = V::Zero(), sv = V::Zero(), suu = V::Zero(), suv = V::Zero(),
    svv = V::Zero();
};

class SplineSurface final : public Surface {
 public:
  SplineSurface(SplineData data, const char* kind) : d_(std::move(data)), kind_(kind) {
    u0_ = d_.knots_u[d_.degree_u];
    du_ = d_.knots_u[d_.count_u] - u0_;
    v0_ = d_.knots_v[d_.degree_v];
    dv_ = d_.knots_v[d_.count_v] - v0_;
    rational_ = !d_.weights.empty();
    bicubic_bezier_ =
        !rational_ && d_.degree_u == 3 && d_.degree_v == 3 && d_.count_u == 4 && d_.count_v == 4;
    points_ = d_.control_points;
    homogeneous_.resize(d_.control_points.size());
    for (size_t i = 0; i < d_.control_points.size(); ++i) {
      const double w = rational_ ? d_.weights[i] : 1.0;
      homogeneous_[i] << d_.control_points[i] * w, w;
    }
  }

  const char* Kind() const override { return kind_; }

  bool ClosedInU() const override { return d_.closed_u; }
  bool ClosedInV() const override { return d_.closed_v; }

  SurfacePoint Evaluate(double u, double v, int order) const override {
    const int p = d_.degree_u;
    const int q = d_.degree_v;
    const double tu = u0_ + u * du_;
    const double tv = v0_ + v * dv_;
    double nu[3][kMaxSplineDegree + 1];
    double nv[3][kMaxSplineDegree + 1];
    const int su = Basis(d_.count_u, p, u, tu, du_, d_.knots_u, order, nu);
    const int sv = Basis(d_.count_v, q, v, tv, dv_, d_.knots_v, order, nv);

    SurfacePoint s;
    if (!rational_ && p == 3 && q == 3) {  // the common bicubic patch: unrolled
      return order == 0   ? CombineBicubic<0>(su - p, sv - q, nu, nv)
             : order == 1 ? CombineBicubic<1>(su - p, sv - q, nu, nv)
                          : CombineBicubic<2>(su - p, sv - q, nu, nv);
    }
    if (!rational_) {
      const Derivs<Vec3> a = Combine<Vec3>(points_, su - p, sv - q, nu, nv, order);
      s.p = a.p;
      s.su = a.su;
      s.sv = a.sv;
      s.suu = a.suu;
      s.suv = a.suv;
      s.svv = a.svv;
      return s;
    }
    const Derivs<Eigen::Vector4d> a =
        Combine<Eigen::Vector4d>(homogeneous_, su - p, sv - q, nu, nv, order);
    const double w = a.p[3];
    s.p = a.p.head<3>() / w;
    if (order >= 1) {
      const double wu = a.su[3];
      const double wv = a.sv[3];
      s.su = (a.su.head<3>() - wu * s.p) / w;
      s.sv = (a.sv.head<3>() - wv * s.p) / w;
      if (order >= 2) {
        s.suu = (a.suu.head<3>() - 2.0 * wu * s.su - a.suu[3] * s.p) / w;
        s.suv = (a.suv.head<3>() - wu * s.sv - wv * s.su - a.suv[3] * s.p) / w;
        s.svv = (a.svv.head<3>() - 2.0 * wv * s.sv - a.svv[3] * s.p) / w;
      }
    }
    return s;
  }

  void EvaluateMany(std::span<const Vec2> uv, int order,
                    std::span<SurfacePoint> out) const override {
    if (!bicubic_bezier_) {
      Surface::EvaluateMany(uv, order, out);
      return;
    }
    ForEachFour(uv, [&](size_t k, size_t lanes, const Lanes& u, const Lanes& v) {
      Lanes d[6][3];
      EvaluateBicubicBezier(u, v, order, d);
      for (size_t l = 0; l < lanes; ++l) out[k + l] = PointOf(d, static_cast<int>(l), order);
    });
  }

  void OffsetMany(std::span<const Vec2> uv, std::span<const double> h,
                  std::span<Vec3> out) const override {
    if (!bicubic_bezier_) {
      Surface::OffsetMany(uv, h, out);
      return;
    }
    ForEachFour(uv, [&](size_t k, size_t lanes, const Lanes& u, const Lanes& v) {
      Lanes height;
      for (size_t l = 0; l < 4; ++l) height[l] = h[k + std::min(l, lanes - 1)];
      Lanes d[6][3];
      BicubicBezier4<1>(points_.data(), u, v, d);
      // OffsetAlongNormal lane by lane: S + h (Su x Sv) / |Su x Sv|.
      const Lanes(&su)[3] = d[1];
      const Lanes(&sv)[3] = d[2];
      const Lanes cross[3] = {su[1] * sv[2] - su[2] * sv[1], su[2] * sv[0] - su[0] * sv[2],
                              su[0] * sv[1] - su[1] * sv[0]};
      const Lanes norm = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
      Lanes moved[3];
      for (int c = 0; c < 3; ++c) moved[c] = d[0][c] + height * (cross[c] / norm);
      for (size_t l = 0; l < lanes; ++l) out[k + l] = Vec3(moved[0][l], moved[1][l], moved[2][l]);
    });
  }

 private:
  // Calls each(k, lanes, u, v) with the parameters of the points k ..
  // k + lanes - 1 (lanes <= 4) as lanes, for k = 0, 4, 8, ...; a short tail
  // repeats its last point.
  template <typename Each>
  static void ForEachFour(std::span<const Vec2> uv, Each&& each) {
    for (size_t k = 0; k < uv.size(); k += 4) {
      const size_t lanes = std::min<size_t>(4, uv.size() - k);
      Lanes u, v;
      for (size_t l = 0; l < 4; ++l) {
        const Vec2& p = uv[k + std::min(l, lanes - 1)];
        u[l] = p.x();
        v[l] = p.y();
      }
      each(k, lanes, u, v);
    }
  }

  void EvaluateBicubicBezier(const Lanes& u, const Lanes& v, int order, Lanes d[6][3]) const {
    if (order == 0) {
      BicubicBezier4<0>(points_.data(), u, v, d);
    } else if (order == 1) {
      BicubicBezier4<1>(points_.data(), u, v, d);
    } else {
      BicubicBezier4<2>(points_.data(), u, v, d);
    }
  }

  // Lane `l` of BicubicBezier4's output.
  static SurfacePoint PointOf(const Lanes d[6][3], int l, int order) {
    SurfacePoint s;
    auto at = [&](int o) { return Vec3(d[o][0][l], d[o][1][l], d[o][2][l]); };
    s.p = at(0);
    if (order >= 1) {
      s.su = at(1);
      s.sv = at(2);
    }
    if (order >= 2) {
      s.suu = at(3);
      s.suv = at(4);
      s.svv = at(5);
    }
    return s;
  }

  // Tensor-product sums of the control values with the basis functions (and
  // their derivatives) of the spans starting at control indices (i0, j0).
  template <typename V>
  Derivs<V> Combine(const std::vector<V>& cps, int i0, int j0,
                    const double nu[3][kMaxSplineDegree + 1],
                    const double nv[3][kMaxSplineDegree + 1], int order) const {
    Derivs<V> out;
    const int p = d_.degree_u;
    const int q = d_.degree_v;
    for (int j = 0; j <= q; ++j) {
      const V* cp = &cps[static_cast<size_t>(j0 + j) * d_.count_u + i0];
      V r0 = V::Zero(), r1 = V::Zero(), r2 = V::Zero();
      for (int i = 0; i <= p; ++i) r0 += nu[0][i] * cp[i];
      out.p += nv[0][j] * r0;
      if (order >= 1) {
        for (int i = 0; i <= p; ++i) r1 += nu[1][i] * cp[i];
        out.su += nv[0][j] * r1;
        out.sv += nv[1][j] * r0;
      }
      if (order >= 2) {
        for (int i = 0; i <= p; ++i) r2 += nu[2][i] * cp[i];
        out.suu += nv[0][j] * r2;
        out.suv += nv[1][j] * r1;
        out.svv += nv[2][j] * r0;
      }
    }
    return out;
  }

  // Combine for non-rational bicubic patches, with the degrees and the order
  // known at compile time so that the loops unroll.
  template <int kOrder>
  SurfacePoint CombineBicubic(int i0, int j0, const double nu[3][kMaxSplineDegree + 1],
                              const double nv[3][kMaxSplineDegree + 1]) const {
    SurfacePoint out;
    for (int j = 0; j < 4; ++j) {
      const Vec3* cp = &points_[static_cast<size_t>(j0 + j) * d_.count_u + i0];
      Vec3 r0 = nu[0][0] * cp[0] + nu[0][1] * cp[1] + nu[0][2] * cp[2] + nu[0][3] * cp[3];
      out.p += nv[0][j] * r0;
      if constexpr (kOrder >= 1) {
        const Vec3 r1 = nu[1][0] * cp[0] + nu[1][1] * cp[1] + nu[1][2] * cp[2] + nu[1][3] * cp[3];
        out.su += nv[0][j] * r1;
        out.sv += nv[1][j] * r0;
        if constexpr (kOrder >= 2) {
          const Vec3 r2 = nu[2][0] * cp[0] + nu[2][1] * cp[1] + nu[2][2] * cp[2] + nu[2][3] * cp[3];
          out.suu += nv[0][j] * r2;
          out.suv += nv[1][j] * r1;
          out.svv += nv[2][j] * r0;
        }
      }
    }
    return out;
  }

  // Basis functions and their derivatives with respect to the [0, 1] parameter
  // x (knot parameter t = t0 + x * scale); returns the knot span.
  static int Basis(int count, int degree, double x, double t, double scale,
                   const std::vector<double>& knots, int order,
                   double ders[3][kMaxSplineDegree + 1]) {
    if (count == degree + 1) {  // a single span: Bernstein polynomials in x
      BernsteinDerivatives(degree, x, order, ders);
      return degree;
    }
    const int span = FindKnotSpan(count, degree, t, knots);
    BasisFunctionDerivatives(span, degree, t, knots, order, ders);
    double f = scale;
    for (int k = 1; k <= order; ++k, f *= scale) {
      for (int j = 0; j <= degree; ++j) ders[k][j] *= f;
    }
    return span;
  }

  SplineData d_;
  const char* kind_;
  std::vector<Vec3> points_;
  std::vector<Eigen::Vector4d> homogeneous_;
  bool rational_ = false;
  bool bicubic_bezier_ = false;  // one span each way, degree 3 x 3, no weights
  double u0_ = 0, du_ = 1, v0_ = 0, dv_ = 1;
};

}  // namespace

std::unique_ptr<Surface> MakeSplineSurface(SplineData data, const char* kind) {
  return std::make_unique<SplineSurface>(std::move(data), kind);
}

Eigen::MatrixXd InterpolateCubicPeriodic(const Eigen::MatrixXd& values,
                                         std::vector<double>* knots) {
  const int n = static_cast<int>(values.rows());
  const int m = n - 1;  // distinct values round the curve
  const int count = n + 2;
  constexpr int p = 3;
  knots->resize(count + p + 1);
  for (int k = 0; k < count + p + 1; ++k) (*knots)[k] = static_cast<double>(k - p) / m;
  // At t_i = i / m the uniform cubic basis weighs control points i, i + 1,
  // i + 2 by 1/6, 4/6, 1/6; control point k is c_{(k - 1) mod m}:
  // (c_{i-1} + 4 c_i + c_{i+1}) / 6 = values[i], cyclic in i.
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m);
  for (int i = 0; i < m; ++i) {
    a(i, (i + m - 1) % m) += 1.0 / 6.0;
    a(i, i) += 4.0 / 6.0;
    a(i, (i + 1) % m) += 1.0 / 6.0;
  }
  const Eigen::MatrixXd c = a.partialPivLu().solve(values.topRows(m));
  Eigen::MatrixXd control(count, values.cols());
  for (int k = 0; k < count; ++k) control.row(k) = c.row((k - 1 + m) % m);
  return control;
}

Eigen::MatrixXd InterpolateCubicNatural(const Eigen::MatrixXd& values, std::vector<double>* knots) {
  const int n = static_cast<int>(values.rows());
  const int count = n + 2;
  constexpr int p = 3;
  knots->assign(count + p + 1, 0.0);
  for (int i = 0; i < n; ++i) (*knots)[p + i] = static_cast<double>(i) / (n - 1);
  for (int i = 0; i <= p; ++i) (*knots)[count + i] = 1.0;

  // Rows 0..n-1: C(t_i) = values[i]; row n: C''(0) = 0; row n+1: C''(1) = 0.
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(count, count);
  double ders[3][kMaxSplineDegree + 1];
  auto add_row = [&](int row, double t, int order) {
    const int span = FindKnotSpan(count, p, t, *knots);
    BasisFunctionDerivatives(span, p, t, *knots, order, ders);
    for (int j = 0; j <= p; ++j) m(row, span - p + j) = ders[order][j];
  };
  for (int i = 0; i < n; ++i) add_row(i, (*knots)[p + i], 0);
  add_row(n, 0.0, 2);
  add_row(n + 1, 1.0, 2);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(count, values.cols());
  rhs.topRows(n) = values;
  return m.partialPivLu().solve(rhs);
}

}  // namespace surfdeform
