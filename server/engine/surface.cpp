#include "engine/surface.hpp"

namespace surfdeform {

Vec3 UnitNormal(const SurfacePoint& s) {
  const Vec3 n = s.su.cross(s.sv);
  const double len = n.norm();
  if (!(len > 0.0)) return Vec3::Zero();
  return n / len;
}

void Surface::EvaluateMany(std::span<const Vec2> uv, int order, std::span<SurfacePoint> out) const {
  for (size_t k = 0; k < uv.size(); ++k) out[k] = Evaluate(uv[k].x(), uv[k].y(), order);
}

}  // namespace surfdeform
