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

}  // namespace surfdeform
