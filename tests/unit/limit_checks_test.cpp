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
  // The refined model (384 B a vertex), the refinement pass's subdivision of
  // it for each frame measured at once, one a thread (1.25 KiB a vertex), and
  // its frames (256 B a frame and vertex) at once. Counting the model and
  // the frames alone, a 2-frame animation of the bunny refined to 431k
  // vertices peaked at 1.18 GB over a 256 MiB budget; one frame holds less
  // than a deformation's bound.
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 1, 2), (size_t{1} << 30) / (384 + 1280 + 256));
  EXPECT_LT(MaxAnimationOutputVertices(limits, 1, 2), MaxOutputVertices(limits));
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 0, 2), MaxAnimationOutputVertices(limits, 1, 2));
  // Two frames on two threads: both measured at once; on one, in turn.
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 2, 2),
            (size_t{1} << 30) / (384 + 2 * 1280 + 2 * 256));
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 2, 1), (size_t{1} << 30) / (384 + 1280 + 2 * 256));
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 2, 0), MaxAnimationOutputVertices(limits, 2, 1));
  // The frame vertices' limit binds where the memory allows more.
  limits.request_memory_bytes = size_t{16} << 30;
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 300, 2), 8'000'000u / 300);
  // A smaller memory budget binds first: 256 MiB over 300 frames.
  limits.request_memory_bytes = 256u << 20;
  EXPECT_EQ(MaxAnimationOutputVertices(limits, 300, 2),
            (size_t{256} << 20) / (384 + 2 * 1280 + 300 * 256));
  // The subdivision's error at that bound says why, in the animation's
  // terms; any other error passes as it is.
  const Status at_bound = Status::LimitExceeded("the subdivision would produce more",
                                                "subdivision.tolerance", 3366, 3400);
  const Status said = AnimationSubdivisionError(limits, 300, 2, at_bound);
  EXPECT_EQ(said.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(said.field(), "subdivision.tolerance");
  EXPECT_EQ(said.limit(), 3366.0);
  EXPECT_EQ(said.actual(), 3400.0);
  EXPECT_NE(said.message().find("300 frames"), std::string::npos) << said.message();
  const Status elsewhere =
      Status::LimitExceeded("the output limit", "subdivision.tolerance", 4e6, 5e6);
  EXPECT_EQ(AnimationSubdivisionError(limits, 300, 2, elsewhere).message(), elsewhere.message());
  const Status late = Status::DeadlineExceeded("late", "request", 60000, 60001);
  EXPECT_EQ(AnimationSubdivisionError(limits, 300, 2, late).code(), ErrorCode::kDeadlineExceeded);
}

FlattenSettings AtRange(int range) {
  FlattenSettings f;
  f.range = range;
  return f;
}

TEST(LimitChecks, AGridsFlatteningIsEstimatedAtItsRange) {
  ServiceLimits limits;
  limits.request_memory_bytes = 512u << 20;
  SamplingOptions grid;
  grid.nu = grid.nv = 256;
  // Range 3: 2.4 KB a sample measured (168 MB estimated); ranges 1 and 2
  // about the same. Range 8 has 144 pairs a sample to range 3's 24: 779 MB
  // measured, 923 MB estimated.
  for (int range : {1, 2, 3}) EXPECT_TRUE(CheckGrid(limits, grid, AtRange(range)).ok()) << range;
  EXPECT_TRUE(CheckGrid(limits, grid, AtRange(5)).ok());  // 344 MB measured
  const Status wide = CheckGrid(limits, grid, AtRange(8));
  EXPECT_EQ(wide.code(), ErrorCode::kLimitExceeded) << wide.ToString();
  EXPECT_EQ(wide.field(), "sampling");
  EXPECT_GT(wide.actual(), 779e6);
  EXPECT_LT(wide.actual(), 1e9);
  // An animation's frames keep more of their paths at a wider range too.
  proto::AnimationRequest frames = Can(180.0, 600, 64);
  limits.request_memory_bytes = 3u << 29;         // 1.5 GiB
  EXPECT_TRUE(CheckFrames(limits, frames).ok());  // 1.26 GB
  frames.flatten.range = 8;
  EXPECT_EQ(CheckFrames(limits, frames).code(), ErrorCode::kLimitExceeded);  // 2.14 GB
}

// The lattice factor scales the distance lattice (its square) and the kept
// paths: 197 bytes asking for a 256 x 256 grid at range 8 and lattice
// factor 16 peaked at 3.77 GB before it was estimated; now it is refused,
// naming the lattice factor, which is what makes it too large.
TEST(LimitChecks, TheLatticeFactorIsInTheFlatteningsEstimate) {
  ServiceLimits limits;  // 1 GiB
  SamplingOptions grid;
  grid.nu = grid.nv = 256;
  FlattenSettings f = AtRange(8);
  EXPECT_TRUE(CheckGrid(limits, grid, f).ok());  // 779 MB measured at the automatic factor
  f.lattice_factor = 16;
  const Status fine = CheckGrid(limits, grid, f);
  EXPECT_EQ(fine.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(fine.field(), "flatten.lattice_factor");
  EXPECT_GT(fine.actual(), 3.77e9);
  f.lattice_factor = 1;  // coarser than the automatic 2: no more than it
  EXPECT_EQ(FlatteningBytes(grid, f), FlatteningBytes(grid, AtRange(8)));
}

TEST(LimitChecks, AMeshSurfacesPairsFitBesideItsVertices) {
  ServiceLimits limits;                                 // 1 GiB, 8M pairs
  EXPECT_TRUE(CheckSurfaceMesh(limits, 200'000).ok());  // 819 MB
  limits.request_memory_bytes = 256u << 20;
  const Status big = CheckSurfaceMesh(limits, 90'601);  // 371 MB
  EXPECT_EQ(big.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(big.field(), "surface.model_id");
  // 192 MiB less 22.8k vertices at 4 KB leaves 482k pairs at 224 B.
  limits.request_memory_bytes = 192u << 20;
  EXPECT_EQ(MaxSurfaceMeshPairs(limits, 22'801), 481'846u);
  EXPECT_EQ(MaxSurfaceMeshPairs(limits, 1'000'000), 1u);  // nothing left
  limits.request_memory_bytes = size_t{64} << 30;
  EXPECT_EQ(MaxSurfaceMeshPairs(limits, 22'801), limits.max_surface_mesh_pairs);
  // The engine's pair limit, when the budget set it, is said as memory.
  limits.request_memory_bytes = 192u << 20;
  const Status engine = Status::LimitExceeded("the mesh has more than 481846 vertex pairs",
                                              "flatten.range", 481'846, 481'847);
  const Status said = SurfaceMeshPairsError(limits, 22'801, engine);
  EXPECT_NE(said.message().find("memory budget of 192 MiB"), std::string::npos) << said.message();
  EXPECT_EQ(said.field(), "flatten.range");
  EXPECT_EQ(said.limit(), 481'846.0);
  const Status pair_limit =
      Status::LimitExceeded("the mesh has more than 8000000", "flatten.range", 8e6, 8e6 + 1);
  limits.request_memory_bytes = size_t{64} << 30;
  EXPECT_EQ(SurfaceMeshPairsError(limits, 22'801, pair_limit).message(), pair_limit.message());
}

TEST(LimitChecks, AMeshAnimationsFramesAndKeysAreCountedPerVertex) {
  ServiceLimits limits;  // 1 GiB
  // 10k vertices: 41 MB for the first flattening, 3.2 MB a frame.
  EXPECT_TRUE(CheckMeshFrames(limits, 300, 2, 10'000).ok());    // 1.0 GB
  const Status many = CheckMeshFrames(limits, 400, 2, 10'000);  // 1.32 GB
  EXPECT_EQ(many.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(many.field(), "animation.frames");
  EXPECT_NE(many.message().find("400 frames of a mesh of 10000 vertices between 2 keyframes"),
            std::string::npos)
      << many.message();
  // The largest mesh a surface may be takes most of the budget alone.
  EXPECT_TRUE(CheckMeshFrames(limits, 2, 2, 200'000).ok());
  EXPECT_EQ(CheckMeshFrames(limits, 10, 2, 200'000).code(), ErrorCode::kLimitExceeded);
  // A key of an uploaded mesh costs its request some 70 bytes and brings
  // the mesh's vertices: 2,000 keys of 100k vertices would hold 4.8 GB.
  const Status keys = CheckMeshFrames(limits, 2, 2'000, 100'000);
  EXPECT_EQ(keys.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(keys.field(), "animation.keyframes");
  EXPECT_TRUE(CheckMeshFrames(limits, 2, 100, 100'000).ok());  // 0.7 GB
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
