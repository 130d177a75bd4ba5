// The rigid motion of the plane that best takes one flat sheet onto another
// of the same grid: an edit of a surface flattens to a sheet much like the
// one before it, but the canonical frame (sample (0, 0) at the origin, its
// first grid edge along +X) turns and shifts with the edit near that corner.
// A client that keeps a model where it was on the surface, through a live
// edit, moves its placement by this motion.
#pragma once

#include <span>

#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform {

// p on the first sheet is near rotation(angle) p + translation on the second.
struct SheetMotion {
  double angle = 0.0;  // radians, counter-clockwise
  Vec2 translation = Vec2::Zero();
  double rms = 0.0;  // what is left: the root mean square distance after the motion

  Vec2 Apply(const Vec2& p) const;
};

// The least-squares rotation and translation (no reflection) taking `from`
// onto `to`, point for point (2D Procrustes: the centroids matched, the
// angle atan2 of the cross and dot sums). kInvalidArgument when the two
// differ in size or hold fewer than two points.
Result<SheetMotion> BestSheetMotion(std::span<const Vec2> from, std::span<const Vec2> to);

}  // namespace surfdeform
