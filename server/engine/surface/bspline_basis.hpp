// B-spline basis functions and their derivatives (Cox-de Boor recursion, in the
// triangular-table form of Piegl & Tiller, "The NURBS Book", 2nd ed., sections
// 2.3-2.5).
#pragma once

#include <vector>

namespace surfdeform {

inline constexpr int kMaxSplineDegree = 15;

// Index k of the knot span [knots[k], knots[k+1]) that holds t, for a clamped
// knot vector of count + degree + 1 values. Parameters before the first span or
// after the last one get that span, so evaluation continues its polynomial.
int FindKnotSpan(int count, int degree, double t, const std::vector<double>& knots);

// ders[d][j]: the d-th derivative (d = 0..max_order, max_order <= 2) of the basis
// function N_{span - degree + j, degree} at t, for j = 0..degree.
// Requires degree <= kMaxSplineDegree and a span with knots[span] < knots[span+1].
void BasisFunctionDerivatives(int span, int degree, double t, const std::vector<double>& knots,
                              int max_order, double ders[3][kMaxSplineDegree + 1]);

// The same for the Bernstein polynomials B_{j,degree}(t), j = 0..degree: the
// basis of a single-span (Bezier) knot vector, computed without divisions.
void BernsteinDerivatives(int degree, double t, int max_order,
                          double ders[3][kMaxSplineDegree + 1]);

// The cubic case spelled out, for one parameter (T = double) or several at
// once (T = Eigen::Array4d, lane by lane): b[d][j] for d = 0..max_order
// (at most 2) and j = 0..3; `b` is any table indexable so.
template <typename T, typename Table>
inline void CubicBernsteinDerivatives(const T& t, int max_order, Table& b) {
  const T s = 1.0 - t;
  b[0][0] = s * s * s;
  b[0][1] = 3.0 * t * s * s;
  b[0][2] = 3.0 * t * t * s;
  b[0][3] = t * t * t;
  if (max_order >= 1) {
    b[1][0] = -3.0 * s * s;
    b[1][1] = 3.0 * s * (s - 2.0 * t);
    b[1][2] = 3.0 * t * (2.0 * s - t);
    b[1][3] = 3.0 * t * t;
  }
  if (max_order >= 2) {
    b[2][0] = 6.0 * s;
    b[2][1] = 6.0 * (t - 2.0 * s);
    b[2][2] = 6.0 * (s - 2.0 * t);
    b[2][3] = 6.0 * t;
  }
}

}  // namespace surfdeform
