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
  // Flattened periodic by stress, the sheet is continued past the seam too,
  // and so is a sphere's with its whole longitude.
  proto::AnimationRequest numeric = Can(360.0, 600, 40);
  numeric.flatten.exact_developable = false;
  EXPECT_EQ(CheckFrames(limits, numeric).code(), ErrorCode::kLimitExceeded);
  proto::AnimationRequest belts = Can(360.0, 600, 40);
  for (Keyframe& key : belts.animation.keyframes) {
    key.surface = SphereSpec{1.0, 0.0, 360.0, -40.0, 40.0, {}};
  }
  EXPECT_EQ(CheckFrames(limits, belts).code(), ErrorCode::kLimitExceeded);
  for (Keyframe& key : belts.animation.keyframes) {
    key.surface = SphereSpec{1.0, 0.0, 180.0, -40.0, 40.0, {}};
  }
  EXPECT_TRUE(CheckFrames(limits, belts).ok());
  // A whole torus, continued past both seams: nine copies of every frame's
  // sheet, so 600 frames of 32 x 32 (2.8 GB estimated) are refused too.
  proto::AnimationRequest tori = Can(360.0, 600, 32);
  for (Keyframe& key : tori.animation.keyframes) {
    key.surface = TorusSpec{3.0, 1.0, 0.0, 360.0, 0.0, 360.0, {}};
  }
  EXPECT_EQ(CheckFrames(limits, tori).code(), ErrorCode::kLimitExceeded);
  tori.animation.frames = 200;
  EXPECT_TRUE(CheckFrames(limits, tori).ok());
}

TEST(LimitChecks, AnAnimationsModelIsBoundedByWhatItsFramesHold) {
  ServiceLimits limits;  // 8M frame vertices, 1 GiB per request, 4M output vertices
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 1), MaxOutputVertices(limits));
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 0), MaxOutputVertices(limits));
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 300), 8'000'000u / 300);
  // A smaller memory budget binds first: 256 MiB over 300 frames at 96 B.
  limits.request_memory_bytes = 256u << 20;
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 300), 9320u);
  // The subdivision's error at that bound says why, in the animation's
  // terms; any other error passes as it is.
  const Status at_bound = Status::LimitExceeded("the subdivision would produce more",
                                                "subdivision.tolerance", 9320, 9400);
  const Status said = AnimationSubdivisionError(limits, 300, at_bound);
  EXPECT_EQ(said.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(said.field(), "subdivision.tolerance");
  EXPECT_EQ(said.limit(), 9320.0);
  EXPECT_EQ(said.actual(), 9400.0);
  EXPECT_NE(said.message().find("300 frames"), std::string::npos) << said.message();
  const Status elsewhere =
      Status::LimitExceeded("the output limit", "subdivision.tolerance", 4e6, 5e6);
  EXPECT_EQ(AnimationSubdivisionError(limits, 300, elsewhere).message(), elsewhere.message());
  const Status late = Status::DeadlineExceeded("late", "request", 60000, 60001);
  EXPECT_EQ(AnimationSubdivisionError(limits, 300, late).code(), ErrorCode::kDeadlineExceeded);
}

TEST(LimitChecks, ClosesInUAgreesWithTheSurfaces) {
  const SurfaceSpec specs[] = {CylinderSpec{1.0, 1.0, 360.0, {}},
                               CylinderSpec{1.0, 1.0, 359.0, {}},
                               ConeSpec{1.0, 0.5, 1.0, 360.0, {}},
                               SphereSpec{1.0, -180.0, 180.0, -40.0, 40.0, {}},
                               SphereSpec{1.0, 0.0, 90.0, -40.0, 40.0, {}},
                               TorusSpec{2.0, 0.5, 0.0, 360.0, -90.0, 90.0, {}},
                               TorusSpec{2.0, 0.5, 0.0, 90.0, 0.0, 360.0, {}},
                               WaveSpec{}};
  int closed = 0;
  for (const SurfaceSpec& spec : specs) {
    auto surface = MakeSurface(spec);
    ASSERT_TRUE(surface.ok()) << surface.status().ToString();
    EXPECT_EQ(ClosesInU(spec), (*surface)->ClosedInU()) << KindName(KindOf(spec));
    EXPECT_EQ(ClosesInV(spec), (*surface)->ClosedInV()) << KindName(KindOf(spec));
    closed += ClosesInU(spec) ? 1 : 0;
  }
  EXPECT_EQ(closed, 4);
}

}  // namespace
}  // namespace surfdeform
