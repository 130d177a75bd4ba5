// Rigid 2D alignment of a flat sheet with a reference, for isometry tests.
#pragma once

#include <vector>

#include "engine/common/geometry_types.hpp"

namespace surfdeform::testing {

// A rotation and a translation of the plane: p -> rotation p + translation.
struct RigidMotion {
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  Vec2 translation = Vec2::Zero();
  Vec2 operator()(const Vec2& p) const { return rotation * p + translation; }
};

// The rotation and translation (no reflection) that best move b onto a in
// the least-squares sense (a[i] and b[i] correspond).
RigidMotion BestRigidMotion(const std::vector<Vec2>& a, const std::vector<Vec2>& b);

// Max distance between `a` and `b` moved by BestRigidMotion(a, b).
double RigidError(const std::vector<Vec2>& a, const std::vector<Vec2>& b);

// RigidError divided by the diameter of `a` (its bounding box diagonal).
double RelativeRigidError(const std::vector<Vec2>& a, const std::vector<Vec2>& b);

}  // namespace surfdeform::testing
