#include "engine/surface.hpp"

namespace surfdeform {

Vec3 UnitNormal(const SurfacePoint& s) {
  const Vec3 n = s.su.cross(s.sv);
  const double len = n.norm();
  if (!(len > 0.0)) return Vec3::Zero();
  return n / len;
}

}  // namespace surfdeform
