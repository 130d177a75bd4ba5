// Small fixed-size vector types shared by the engine (Eigen, double precision).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace surfdeform {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

// The 2D cross product a.x b.y - a.y b.x: twice the signed area of the
// triangle (0, a, b), positive when b is counter-clockwise from a.
inline double Cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace surfdeform
