// Rigid 2D alignment of a flat sheet with a reference, for isometry tests.
#pragma once

#include <vector>

#include "engine/geometry_types.hpp"

namespace surfdeform::testing {

// Max distance between `a` and `b` after the rotation and translation (no
// reflection) that best aligns b onto a in the least-squares sense, divided by
// the diameter of `a` (its bounding box diagonal).
double RelativeRigidError(const std::vector<Vec2>& a, const std::vector<Vec2>& b);

}  // namespace surfdeform::testing
