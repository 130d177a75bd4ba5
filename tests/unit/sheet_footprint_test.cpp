// A model's footprint on a sheet, recorded by one deformation and given to
// the next: the same result, bit for bit, in every mode of the map.
#include "engine/sheet/sheet_footprint.hpp"

#include <gtest/gtest.h>

#include <string>

#include "engine/deform/deform.hpp"
#include "engine/surface/surface_spec.hpp"
#include "support/given_memo.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

using testing::Flattened;
using testing::GivenMemo;
using testing::Target;

DeformResult DeformOk(const Target& t, const Mesh& m, const PlacementOptions& o,
                      const SubdivisionOptions& sub, GivenMemo memo) {
  auto r = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o, .subdivision = sub}, &memo);
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? std::move(r).value() : DeformResult{};
}

// Deforms recording the footprint, and with the footprint `known`.
DeformResult Recording(const Target& t, const Mesh& m, const PlacementOptions& o,
                       const SubdivisionOptions& sub) {
  GivenMemo memo;
  memo.record_footprint = true;
  return DeformOk(t, m, o, sub, memo);
}
DeformResult Replaying(const Target& t, const Mesh& m, const PlacementOptions& o,
                       const SubdivisionOptions& sub, const SheetFootprint& known) {
  GivenMemo memo;
  memo.footprint = std::make_shared<const SheetFootprint>(known);
  return DeformOk(t, m, o, sub, memo);
}

void ExpectSameBits(const DeformResult& a, const DeformResult& b, const std::string& what) {
  EXPECT_EQ(a.mesh.positions, b.mesh.positions) << what;
  EXPECT_EQ(a.mesh.normals, b.mesh.normals) << what;
  EXPECT_EQ(a.mesh.tangents, b.mesh.tangents) << what;
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles) << what;
  EXPECT_EQ(a.stats.outside, b.stats.outside) << what;
  EXPECT_EQ(a.stats.max_outside_distance, b.stats.max_outside_distance) << what;
  EXPECT_EQ(a.stats.subdivision.vertices_after, b.stats.subdivision.vertices_after) << what;
}

Mesh WithoutFrame(Mesh m) {
  m.normals.clear();
  m.tangents.clear();
  return m;
}

// Fine and coarse grids (the coarse one is refined by the subdivision), with
// and without normals and tangents, without subdivision and with each mode:
// fresh, recording, and replaying the recorded footprint agree bit for bit.
TEST(SheetFootprint, ARecordedFootprintGivesTheSameDeformation) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  const Mesh fine = testing::FlatGrid(-3, -3, 6, 6, 90, 90, 0.2);
  const Mesh coarse = testing::FlatGrid(-3, -3, 6, 6, 3, 3, 0.2);
  const struct {
    const char* name;
    Mesh mesh;
  } models[] = {{"fine", fine},
                {"fine, no frame", WithoutFrame(fine)},
                {"coarse", coarse},
                {"coarse, no frame", WithoutFrame(coarse)}};
  for (const auto& model : models) {
    for (SubdivisionMode mode :
         {SubdivisionMode::kOff, SubdivisionMode::kAdaptive, SubdivisionMode::kUniform}) {
      const std::string what = std::string(model.name) + ", " + SubdivisionModeName(mode);
      PlacementOptions o;
      o.fit = true;
      SubdivisionOptions sub;
      sub.mode = mode;
      const DeformResult fresh = DeformOk(t, model.mesh, o, sub, {});
      const DeformResult recorded = Recording(t, model.mesh, o, sub);
      const SheetFootprint& footprint = recorded.footprint;
      ASSERT_EQ(footprint.location.size(), model.mesh.positions.size()) << what;
      for (size_t k = 0; k < footprint.location.size(); ++k) {
        ASSERT_GE(footprint.location[k].i, 0) << what << ": vertex " << k << " not recorded";
      }
      const DeformResult replayed = Replaying(t, model.mesh, o, sub, footprint);
      EXPECT_TRUE(replayed.footprint.location.empty()) << what;
      ExpectSameBits(fresh, recorded, what + ", recording");
      ExpectSameBits(fresh, replayed, what + ", replayed");
      if (mode == SubdivisionMode::kUniform && model.mesh.positions.size() < 100) {
        EXPECT_GT(fresh.mesh.positions.size(), model.mesh.positions.size()) << what;
      }
    }
  }
}

// Vertices off the sheet are not kept (their parameters depend on the
// outside mode): they are located again, and clamped or extrapolated as
// before.
TEST(SheetFootprint, VerticesOffTheSheetAreLocatedAgain) {
  // The sheet is about 10 wide; the grid's outer columns are off it.
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  const Mesh m = testing::FlatGrid(-8.0, -2.0, 16.0, 4.0, 8, 2, 0.1);
  for (OutsideMode mode : {OutsideMode::kClamp, OutsideMode::kExtrapolate}) {
    PlacementOptions o;
    o.outside = mode;
    const SubdivisionOptions off = SubdivisionIn(SubdivisionMode::kOff);
    const DeformResult recorded = Recording(t, m, o, off);
    EXPECT_GT(recorded.stats.outside, 0u);
    EXPECT_LT(recorded.stats.outside, m.positions.size());
    size_t off_sheet = 0;
    for (const SheetLocation& l : recorded.footprint.location) off_sheet += l.i < 0;
    EXPECT_EQ(off_sheet, recorded.stats.outside);
    ExpectSameBits(recorded, Replaying(t, m, o, off, recorded.footprint),
                   std::string(NameOf<OutsideMode>(kOutsideModes, mode)));
  }
}

// A cylinder unrolled in closed form locates no cell: nothing to record.
TEST(SheetFootprint, ASheetUnrolledInClosedFormRecordsNone) {
  const Target t = Flattened(CylinderSpec{1.0, 1.0, 90.0, {}}, 8);
  ASSERT_EQ(t.sheet.method, "exact");
  const Mesh m = testing::FlatGrid(-0.5, -0.25, 1.0, 0.5, 4, 2, 0.0);
  const DeformResult r = Recording(t, m, {}, {});
  EXPECT_TRUE(r.footprint.location.empty());
  EXPECT_EQ(r.mesh.positions, DeformOk(t, m, {}, {}, {}).mesh.positions);
}

// The footprint given is what the map reads (a vertex moved to another cell
// lands elsewhere), and one of another size is ignored.
TEST(SheetFootprint, TheGivenFootprintIsReadAndAWrongSizedOneIgnored) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  const Mesh m = WithoutFrame(testing::FlatGrid(-3, -3, 6, 6, 20, 20, 0.2));
  PlacementOptions o;
  o.fit = true;
  const SubdivisionOptions off = SubdivisionIn(SubdivisionMode::kOff);
  const DeformResult recorded = Recording(t, m, o, off);
  SheetFootprint moved = recorded.footprint;
  SheetLocation& l = moved.location[7];
  l.i = l.i > 0 ? l.i - 1 : l.i + 1;
  const DeformResult misled = Replaying(t, m, o, off, moved);
  EXPECT_NE(misled.mesh.positions[7], recorded.mesh.positions[7]);
  EXPECT_EQ(misled.mesh.positions[8], recorded.mesh.positions[8]);

  moved.location.pop_back();
  ExpectSameBits(recorded, Replaying(t, m, o, off, moved), "wrong size");
}

}  // namespace
}  // namespace surfdeform
