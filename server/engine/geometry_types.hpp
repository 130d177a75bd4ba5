// Small fixed-size vector types shared by the engine (Eigen, double precision).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace surfdeform {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

}  // namespace surfdeform
