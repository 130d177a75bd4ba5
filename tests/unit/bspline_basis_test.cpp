#include "engine/surface/bspline_basis.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace surfdeform {
namespace {

using Table = double[3][kMaxSplineDegree + 1];

TEST(BSplineBasis, PartitionOfUnityAndZeroDerivativeSum) {
  const std::vector<double> knots = {0, 0, 0, 0, 0.2, 0.5, 0.5, 0.9, 1, 1, 1, 1};
  const int count = static_cast<int>(knots.size()) - 4;
  for (double t : {0.0, 0.1, 0.2, 0.35, 0.5, 0.7, 0.95, 1.0}) {
    Table d;
    const int span = FindKnotSpan(count, 3, t, knots);
    BasisFunctionDerivatives(span, 3, t, knots, 2, d);
    double s0 = 0, s1 = 0, s2 = 0;
    for (int j = 0; j <= 3; ++j) {
      s0 += d[0][j];
      s1 += d[1][j];
      s2 += d[2][j];
      EXPECT_GE(d[0][j], -1e-15);
    }
    EXPECT_NEAR(s0, 1.0, 1e-14) << t;
    EXPECT_NEAR(s1, 0.0, 1e-12) << t;
    EXPECT_NEAR(s2, 0.0, 1e-10) << t;
  }
}

TEST(BSplineBasis, DerivativesMatchFiniteDifferences) {
  const std::vector<double> knots = {0, 0, 0, 0, 0.3, 0.6, 1, 1, 1, 1};
  const int count = 6;
  const double t = 0.45, h = 1e-5;
  Table d, dp, dm;
  const int span = FindKnotSpan(count, 3, t, knots);
  BasisFunctionDerivatives(span, 3, t, knots, 2, d);
  BasisFunctionDerivatives(span, 3, t + h, knots, 1, dp);
  BasisFunctionDerivatives(span, 3, t - h, knots, 1, dm);
  for (int j = 0; j <= 3; ++j) {
    EXPECT_NEAR(d[1][j], (dp[0][j] - dm[0][j]) / (2 * h), 1e-7);
    EXPECT_NEAR(d[2][j], (dp[1][j] - dm[1][j]) / (2 * h), 1e-5);
  }
}

TEST(BSplineBasis, BernsteinEqualsSingleSpanBSplineForEveryDegree) {
  for (int p = 1; p <= kMaxSplineDegree; ++p) {
    std::vector<double> knots(p + 1, 0.0);
    knots.resize(2 * (p + 1), 1.0);
    for (double t : {0.0, 0.13, 0.5, 0.77, 1.0}) {
      Table a, b;
      BasisFunctionDerivatives(FindKnotSpan(p + 1, p, t, knots), p, t, knots, 2, a);
      BernsteinDerivatives(p, t, 2, b);
      for (int k = 0; k <= 2; ++k) {
        for (int j = 0; j <= p; ++j) {
          EXPECT_NEAR(a[k][j], b[k][j], 1e-9 * (1 + std::abs(a[k][j])))
              << "degree " << p << " t " << t << " order " << k << " j " << j;
        }
      }
    }
  }
}

TEST(BSplineBasis, FindKnotSpanClampsOutsideTheRange) {
  const std::vector<double> knots = {0, 0, 0, 0.5, 1, 1, 1};
  EXPECT_EQ(FindKnotSpan(4, 2, -0.1, knots), 2);
  EXPECT_EQ(FindKnotSpan(4, 2, 0.0, knots), 2);
  EXPECT_EQ(FindKnotSpan(4, 2, 0.5, knots), 3);
  EXPECT_EQ(FindKnotSpan(4, 2, 1.0, knots), 3);
  EXPECT_EQ(FindKnotSpan(4, 2, 1.2, knots), 3);
}

}  // namespace
}  // namespace surfdeform
