#include "engine/flatten/sheet_trend.hpp"

#include <algorithm>
#include <cmath>

#include "engine/common/flat_sheet.hpp"

namespace surfdeform {

SheetTrend TrendBetween(const FlatSheet& before, const FlatSheet& after) {
  SheetTrend t;
  const size_t n = after.flat.size();
  if (before.nu != after.nu || before.nv != after.nv || before.flat.size() != n ||
      before.points.size() != n || after.points.size() != n) {
    return t;
  }
  if (!before.period_u.isZero() || !before.period_v.isZero() || !after.period_u.isZero() ||
      !after.period_v.isZero()) {
    return t;
  }
  t.points.resize(n);
  t.flat.resize(n);
  for (size_t k = 0; k < n; ++k) {
    t.points[k] = after.points[k] - before.points[k];
    t.flat[k] = after.flat[k] - before.flat[k];
  }
  return t;
}

double TrendStep(const SheetTrend& trend, std::span<const Vec3> from, std::span<const Vec3> now) {
  const size_t n = trend.points.size();
  if (n == 0 || from.size() != n || now.size() != n || trend.flat.size() != n) return 0.0;
  double along = 0.0, norm = 0.0;
  for (size_t k = 0; k < n; ++k) {
    along += (now[k] - from[k]).dot(trend.points[k]);
    norm += trend.points[k].squaredNorm();
  }
  if (!(norm > 0.0)) return 0.0;
  const double step = along / norm;
  return std::isfinite(step) ? std::clamp(step, -2.0, 2.0) : 0.0;
}

std::vector<Vec2> Extrapolated(std::span<const Vec2> flat, const SheetTrend& trend, double step) {
  std::vector<Vec2> out(flat.begin(), flat.end());
  if (trend.flat.size() != out.size()) return out;
  for (size_t k = 0; k < out.size(); ++k) out[k] += step * trend.flat[k];
  return out;
}

}  // namespace surfdeform
