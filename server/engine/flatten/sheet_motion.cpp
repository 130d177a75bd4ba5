#include "engine/flatten/sheet_motion.hpp"

#include <cmath>

namespace surfdeform {

Vec2 SheetMotion::Apply(const Vec2& p) const {
  const double c = std::cos(angle), s = std::sin(angle);
  return Vec2(c * p.x() - s * p.y(), s * p.x() + c * p.y()) + translation;
}

Result<SheetMotion> BestSheetMotion(std::span<const Vec2> from, std::span<const Vec2> to) {
  if (from.size() != to.size() || from.size() < 2) {
    return InvalidArgument("a sheet motion needs two sheets of the same samples, at least two");
  }
  Vec2 ca = Vec2::Zero(), cb = Vec2::Zero();
  for (size_t k = 0; k < from.size(); ++k) {
    ca += from[k];
    cb += to[k];
  }
  ca /= static_cast<double>(from.size());
  cb /= static_cast<double>(to.size());
  double dot = 0.0, cross = 0.0;
  for (size_t k = 0; k < from.size(); ++k) {
    const Vec2 a = from[k] - ca, b = to[k] - cb;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  SheetMotion m;
  m.angle = std::atan2(cross, dot);
  m.translation = cb - SheetMotion{m.angle, Vec2::Zero(), 0.0}.Apply(ca);
  double sum = 0.0;
  for (size_t k = 0; k < from.size(); ++k) sum += (m.Apply(from[k]) - to[k]).squaredNorm();
  m.rms = std::sqrt(sum / static_cast<double>(from.size()));
  return m;
}

}  // namespace surfdeform
