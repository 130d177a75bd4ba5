#include "support/sheet_compare.hpp"

#include <algorithm>
#include <cmath>

namespace surfdeform::testing {

RigidMotion BestRigidMotion(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  const size_t n = a.size();
  Vec2 ca = Vec2::Zero(), cb = Vec2::Zero();
  for (size_t i = 0; i < n; ++i) {
    ca += a[i];
    cb += b[i];
  }
  ca /= static_cast<double>(n);
  cb /= static_cast<double>(n);
  double dot = 0.0, cross = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 p = a[i] - ca, q = b[i] - cb;
    dot += p.dot(q);
    cross += q.x() * p.y() - q.y() * p.x();
  }
  const double angle = std::atan2(cross, dot);
  const double c = std::cos(angle), s = std::sin(angle);
  RigidMotion m;
  m.rotation << c, -s, s, c;
  m.translation = ca - m.rotation * cb;
  return m;
}

double RigidError(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  const RigidMotion m = BestRigidMotion(a, b);
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, (m(b[i]) - a[i]).norm());
  return worst;
}

double RelativeRigidError(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  Eigen::AlignedBox2d box;
  for (const Vec2& p : a) box.extend(p);
  return RigidError(a, b) / box.diagonal().norm();
}

}  // namespace surfdeform::testing
