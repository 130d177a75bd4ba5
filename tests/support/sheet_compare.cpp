#include "support/sheet_compare.hpp"

#include <algorithm>
#include <cmath>

namespace surfdeform::testing {

double RelativeRigidError(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  const size_t n = a.size();
  Vec2 ca = Vec2::Zero(), cb = Vec2::Zero();
  for (size_t i = 0; i < n; ++i) {
    ca += a[i];
    cb += b[i];
  }
  ca /= static_cast<double>(n);
  cb /= static_cast<double>(n);
  double dot = 0.0, cross = 0.0;
  Eigen::AlignedBox2d box;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 p = a[i] - ca, q = b[i] - cb;
    dot += p.dot(q);
    cross += q.x() * p.y() - q.y() * p.x();
    box.extend(a[i]);
  }
  const double angle = std::atan2(cross, dot);
  const double c = std::cos(angle), s = std::sin(angle);
  double worst = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 q = b[i] - cb;
    const Vec2 moved(c * q.x() - s * q.y(), s * q.x() + c * q.y());
    worst = std::max(worst, (moved - (a[i] - ca)).norm());
  }
  return worst / box.diagonal().norm();
}

}  // namespace surfdeform::testing
