// The estimates made before the work (service/limit_checks.hpp): an
// animation of a whole cylinder, whose every frame's map is continued past
// the seam, is estimated at what it takes.
#include "service/limit_checks.hpp"

#include <gtest/gtest.h>

namespace surfdeform {
namespace {

proto::AnimationRequest Can(double angle_deg, int frames, int side) {
  proto::AnimationRequest r;
  r.animation.keyframes = {{0.0, CylinderSpec{2.0, 3.0, angle_deg, {}}},
                           {1.0, CylinderSpec{3.0, 3.0, angle_deg, {}}}};
  r.animation.frames = frames;
  r.sampling.nu = r.sampling.nv = side;
  return r;
}

TEST(LimitChecks, AnAnimationAcrossTheSeamIsEstimatedAtItsMapsCost) {
  ServiceLimits limits;  // 1 GiB per request, 600 frames
  // 600 frames of 40 x 40: 0.5 GB as an open sheet; 1.5 GB continued past
  // the seam (measured 1.1 KB per frame and sample at 32 x 32).
  EXPECT_TRUE(CheckFrames(limits, Can(180.0, 600, 40)).ok());
  const Status closed = CheckFrames(limits, Can(360.0, 600, 40));
  EXPECT_EQ(closed.code(), ErrorCode::kLimitExceeded) << closed.ToString();
  EXPECT_EQ(closed.field(), "animation.frames");
  // 600 frames of 32 x 32 fit (0.94 GB estimated; 0.68 GB peak measured).
  EXPECT_TRUE(CheckFrames(limits, Can(360.0, 600, 32)).ok());
  // Flattened numerically, the sheet is not continued past the seam.
  proto::AnimationRequest numeric = Can(360.0, 600, 40);
  numeric.flatten.exact_developable = false;
  EXPECT_TRUE(CheckFrames(limits, numeric).ok());
}

}  // namespace
}  // namespace surfdeform
