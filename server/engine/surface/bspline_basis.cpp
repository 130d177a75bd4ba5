#include "engine/surface/bspline_basis.hpp"

#include <algorithm>

namespace surfdeform {

int FindKnotSpan(int count, int degree, double t, const std::vector<double>& knots) {
  const int last = count - 1;  // last span that can be non-empty is [knots[last], knots[last+1])
  if (t >= knots[last + 1]) {
    // Last non-empty span (skip a repeated end knot run).
    int k = last;
    while (k > degree && knots[k] >= knots[last + 1]) --k;
    return k;
  }
  if (t <= knots[degree]) {
    int k = degree;
    while (k < last && knots[k + 1] <= knots[degree]) ++k;
    return k;
  }
  // Binary search: knots[k] <= t < knots[k+1].
  auto it = std::upper_bound(knots.begin() + degree, knots.begin() + last + 2, t);
  return static_cast<int>(it - knots.begin()) - 1;
}

void BasisFunctionDerivatives(int span, int degree, double t, const std::vector<double>& knots,
                              int max_order, double ders[3][kMaxSplineDegree + 1]) {
  constexpr int kN = kMaxSplineDegree + 1;
  const int p = degree;
  double ndu[kN][kN];
  double left[kN];
  double right[kN];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knots[span + 1 - j];
    right[j] = knots[span + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      // Lower triangle: knot differences; upper triangle: basis functions.
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
  const int n = std::min(max_order, p);
  for (int k = n + 1; k <= max_order; ++k) {
    for (int j = 0; j <= p; ++j) ders[k][j] = 0.0;
  }
  if (n == 0) return;

  double a[2][kN];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0;
    int s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= n; ++k) {
      double d = 0.0;
      const int rk = r - k;
      const int pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= n; ++k) {
    for (int j = 0; j <= p; ++j) ders[k][j] *= factor;
    factor *= (p - k);
  }
}

void BernsteinDerivatives(int degree, double t, int max_order,
                          double ders[3][kMaxSplineDegree + 1]) {
  const int p = degree;
  const double s = 1.0 - t;
  if (p == 3) {  // the common bicubic patch
    CubicBernsteinDerivatives(t, max_order, ders);
    return;
  }
  // b: Bernstein polynomials of degree k, raised in place; lo and mid keep the
  // degrees p - 2 and p - 1 for the derivatives (zero where the index is out of
  // range, which the formulas below need).
  double b[kMaxSplineDegree + 1];
  double lo[kMaxSplineDegree + 3] = {};
  double mid[kMaxSplineDegree + 3] = {};
  b[0] = 1.0;
  for (int k = 0;; ++k) {
    if (k == p - 2) {
      for (int j = 0; j <= k; ++j) lo[j + 1] = b[j];
    }
    if (k == p - 1) {
      for (int j = 0; j <= k; ++j) mid[j + 1] = b[j];
    }
    if (k == p) break;
    b[k + 1] = t * b[k];
    for (int j = k; j > 0; --j) b[j] = s * b[j] + t * b[j - 1];
    b[0] *= s;
  }
  for (int j = 0; j <= p; ++j) ders[0][j] = b[j];
  if (max_order >= 1) {
    // B'_{j,p} = p (B_{j-1,p-1} - B_{j,p-1}); mid[j + 1] = B_{j,p-1}
    for (int j = 0; j <= p; ++j) ders[1][j] = p * (mid[j] - mid[j + 1]);
  }
  if (max_order >= 2) {
    // B''_{j,p} = p (p - 1) (B_{j-2,p-2} - 2 B_{j-1,p-2} + B_{j,p-2}); lo[j + 1] = B_{j,p-2}
    for (int j = 0; j <= p; ++j) {
      const double a = j >= 1 ? lo[j - 1] : 0.0;
      ders[2][j] = p < 2 ? 0.0 : p * (p - 1) * (a - 2.0 * lo[j] + lo[j + 1]);
    }
  }
}

}  // namespace surfdeform
