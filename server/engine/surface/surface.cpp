#include "engine/surface/surface.hpp"

namespace surfdeform {

void Surface::EvaluateMany(std::span<const Vec2> uv, int order, std::span<SurfacePoint> out) const {
  for (size_t k = 0; k < uv.size(); ++k) out[k] = Evaluate(uv[k].x(), uv[k].y(), order);
}

void Surface::OffsetMany(std::span<const Vec2> uv, std::span<const double> h,
                         std::span<Vec3> out) const {
  for (size_t k = 0; k < uv.size(); ++k) {
    out[k] = OffsetAlongNormal(Evaluate(uv[k].x(), uv[k].y(), 1), h[k]);
  }
}

}  // namespace surfdeform
