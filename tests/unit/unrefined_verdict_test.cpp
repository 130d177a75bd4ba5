// A subdivision that added nothing, told to the next deformation of the same
// model (DeformMemo::RecallUnrefined): it is skipped, and the result is the same
// bits as running it.
#include <gtest/gtest.h>

#include <string>

#include "engine/deform/deform.hpp"
#include "support/given_memo.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

using testing::Flattened;
using testing::GivenMemo;
using testing::Target;

DeformResult DeformOk(const Target& t, const Mesh& m, const SubdivisionOptions& sub, GivenMemo memo,
                      bool distortion = false) {
  PlacementOptions o;
  o.fit = true;
  auto r = Deform(SheetMap(*t.surface, t.sheet), m,
                  {.placement = o, .subdivision = sub, .distortion = distortion}, &memo);
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? std::move(r).value() : DeformResult{};
}

Mesh WithoutFrame(Mesh m) {
  m.normals.clear();
  m.tangents.clear();
  return m;
}

void ExpectSameBits(const DeformResult& a, const DeformResult& b, const std::string& what) {
  EXPECT_EQ(a.mesh.positions, b.mesh.positions) << what;
  EXPECT_EQ(a.mesh.normals, b.mesh.normals) << what;
  EXPECT_EQ(a.mesh.tangents, b.mesh.tangents) << what;
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles) << what;
  EXPECT_EQ(a.mesh.distortion, b.mesh.distortion) << what;
  EXPECT_EQ(a.stats.outside, b.stats.outside) << what;
  EXPECT_EQ(a.stats.subdivision.vertices_after, b.stats.subdivision.vertices_after) << what;
  EXPECT_EQ(a.stats.subdivision.max_deviation, b.stats.subdivision.max_deviation) << what;
  EXPECT_EQ(a.stats.subdivision.measured_points, b.stats.subdivision.measured_points) << what;
}

// A fine grid needs nothing from the adaptive subdivision: with and without
// normals, with and without a recorded footprint, the verdict's replay is the
// fresh deformation bit for bit (distortion map included), and it does not
// subdivide.
TEST(UnrefinedVerdict, ReplayingAnUnrefinedVerdictGivesTheSameBits) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  const Mesh fine = testing::FlatGrid(-3, -3, 6, 6, 90, 90, 0.2);
  const SubdivisionOptions adaptive = SubdivisionIn(SubdivisionMode::kAdaptive);
  for (const Mesh& m : {fine, WithoutFrame(fine)}) {
    const std::string what = m.normals.empty() ? "no frame" : "with frame";
    GivenMemo recording;
    recording.record_footprint = true;
    const DeformResult fresh = DeformOk(t, m, adaptive, recording, true);
    ASSERT_TRUE(fresh.unrefined) << what;
    ASSERT_EQ(fresh.mesh.positions.size(), m.positions.size()) << what;
    ASSERT_GT(fresh.stats.subdivision.measured_points, 0u) << what;
    EXPECT_GT(fresh.stats.subdivide_ms, 0.0) << what;

    for (const bool with_footprint : {false, true}) {
      GivenMemo given;
      given.unrefined = fresh.stats.subdivision;
      if (with_footprint) given.footprint = std::make_shared<const SheetFootprint>(fresh.footprint);
      const DeformResult replayed = DeformOk(t, m, adaptive, given, true);
      const std::string how = what + (with_footprint ? ", footprint known" : ", footprint found");
      EXPECT_TRUE(replayed.unrefined) << how;
      EXPECT_EQ(replayed.stats.subdivide_ms, 0.0) << how;
      EXPECT_EQ(replayed.stats.subdivision.time_ms, 0.0) << how;
      EXPECT_EQ(replayed.stats.subdivision.mode, SubdivisionMode::kAdaptive) << how;
      ExpectSameBits(fresh, replayed, how);
    }
    // A verdict to record a footprint with: it is recorded by the map.
    GivenMemo both = recording;
    both.unrefined = fresh.stats.subdivision;
    const DeformResult replayed = DeformOk(t, m, adaptive, both, true);
    EXPECT_EQ(replayed.footprint.location.size(), m.positions.size()) << what;
    EXPECT_EQ(replayed.footprint.location.size(), fresh.footprint.location.size()) << what;
    for (size_t k = 0; k < replayed.footprint.location.size(); ++k) {
      ASSERT_EQ(replayed.footprint.location[k].i, fresh.footprint.location[k].i) << what << k;
      ASSERT_EQ(replayed.footprint.location[k].j, fresh.footprint.location[k].j) << what << k;
    }
  }
}

// A coarse grid is refined: no verdict. Without subdivision there is none to
// give, and a verdict given then is not read.
TEST(UnrefinedVerdict, OnlyASubdivisionThatAddedNothingGivesOne) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  const Mesh coarse = testing::FlatGrid(-3, -3, 6, 6, 3, 3, 0.2);
  const DeformResult refined = DeformOk(t, coarse, SubdivisionIn(SubdivisionMode::kAdaptive), {});
  EXPECT_FALSE(refined.unrefined);
  EXPECT_GT(refined.mesh.positions.size(), coarse.positions.size());

  const SubdivisionOptions off = SubdivisionIn(SubdivisionMode::kOff);
  const DeformResult plain = DeformOk(t, coarse, off, {});
  EXPECT_FALSE(plain.unrefined);
  GivenMemo given;
  given.unrefined = refined.stats.subdivision;
  const DeformResult unsubdivided = DeformOk(t, coarse, off, given);
  EXPECT_FALSE(unsubdivided.unrefined);
  EXPECT_EQ(unsubdivided.stats.subdivision.mode, SubdivisionMode::kOff);
  ExpectSameBits(plain, unsubdivided, "off, verdict given");
}

}  // namespace
}  // namespace surfdeform
