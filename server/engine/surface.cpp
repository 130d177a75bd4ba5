#include "engine/surface.hpp"

namespace surfdeform {

void Surface::EvaluateMany(std::span<const Vec2> uv, int order, std::span<SurfacePoint> out) const {
  for (size_t k = 0; k < uv.size(); ++k) out[k] = Evaluate(uv[k].x(), uv[k].y(), order);
}

}  // namespace surfdeform
