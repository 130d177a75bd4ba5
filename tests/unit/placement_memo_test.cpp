// The service's memo of placements: keys that tell models, surfaces and
// options apart, and a bounded least-recently-used store, with the verdicts
// of subdivisions that added nothing.
#include "service/placement_memo.hpp"

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <vector>

namespace surfdeform {
namespace {

std::vector<Vec3> Square() { return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}; }

Placement WithScale(double scale) {
  Placement p;
  p.scale = scale;
  return p;
}

TEST(PlacementMemo, KeysTellModelsSurfacesAndOptionsApart) {
  const PlacementMemo memo(8);
  PlacementOptions o;
  o.fit = true;
  const auto key = memo.KeyOf("surface-a", o, Square());
  EXPECT_EQ(memo.KeyOf("surface-a", o, Square()), key);

  PlacementOptions threads = o;
  threads.threads = 7;  // how many threads place it does not change where
  EXPECT_EQ(memo.KeyOf("surface-a", threads, Square()), key);

  std::vector<Vec3> moved = Square();
  moved[2].z() = 1e-12;
  EXPECT_NE(memo.KeyOf("surface-a", o, moved), key);
  std::vector<Vec3> fewer = Square();
  fewer.pop_back();
  EXPECT_NE(memo.KeyOf("surface-a", o, fewer), key);
  EXPECT_NE(memo.KeyOf("surface-b", o, Square()), key);

  PlacementOptions other = o;
  other.rotation_deg = 90;
  EXPECT_NE(memo.KeyOf("surface-a", other, Square()), key);
  other = o;
  other.fit_margin = 0.05;
  EXPECT_NE(memo.KeyOf("surface-a", other, Square()), key);
  other = o;
  other.center = Vec2(0.25, 0);
  EXPECT_NE(memo.KeyOf("surface-a", other, Square()), key);
  other = o;
  other.y_up_input = true;
  EXPECT_NE(memo.KeyOf("surface-a", other, Square()), key);
  other = o;
  other.up = UpAxis::kNegZ;
  EXPECT_NE(memo.KeyOf("surface-a", other, Square()), key);

  // Another process (memo) seeds its digests differently.
  const PlacementMemo elsewhere(8);
  EXPECT_NE(elsewhere.KeyOf("surface-a", o, Square()), key);
}

TEST(PlacementMemo, FindsWhatWasStoredAndDropsTheLeastRecentlyUsed) {
  PlacementMemo memo(2);
  const PlacementOptions o;
  const auto a = memo.KeyOf("a", o, Square()), b = memo.KeyOf("b", o, Square()),
             c = memo.KeyOf("c", o, Square());
  EXPECT_FALSE(memo.Find(a).has_value());
  memo.Store(a, WithScale(1.5));
  memo.Store(b, WithScale(2.5));
  ASSERT_TRUE(memo.Find(a).has_value());  // a becomes the most recent
  EXPECT_EQ(memo.Find(a)->placement.scale, 1.5);
  memo.Store(c, WithScale(3.5));  // drops b, the least recently used
  EXPECT_FALSE(memo.Find(b).has_value());
  ASSERT_TRUE(memo.Find(c).has_value());
  EXPECT_EQ(memo.Find(c)->placement.scale, 3.5);
  memo.Store(c, WithScale(9.0));  // stored again by a concurrent request: kept as it was
  EXPECT_EQ(memo.Find(c)->placement.scale, 3.5);

  const PlacementMemoStats stats = memo.stats();
  EXPECT_EQ(stats.entries, 2u);
  EXPECT_EQ(stats.capacity, 2u);
  EXPECT_EQ(stats.hits, 5u);
  EXPECT_EQ(stats.misses, 2u);
}

// A subdivision's key tells options (but the thread count and the time
// budget) and triangles apart.
TEST(PlacementMemo, SubdivisionKeysTellOptionsAndTrianglesApart) {
  const PlacementMemo memo(8);
  const std::vector<std::array<uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  const SubdivisionOptions o = SubdivisionIn(SubdivisionMode::kAdaptive);
  const auto key = memo.SubdivisionKeyOf(o, triangles);
  SubdivisionOptions same = o;
  same.threads = 3;
  same.time_budget_ms = 250;
  EXPECT_EQ(memo.SubdivisionKeyOf(same, triangles), key);
  for (auto change : std::vector<void (*)(SubdivisionOptions*)>{
           [](SubdivisionOptions* s) { s->mode = SubdivisionMode::kUniform; },
           [](SubdivisionOptions* s) { s->epsilon = 0.5; },
           [](SubdivisionOptions* s) { s->tolerance = 1e-4; },
           [](SubdivisionOptions* s) { s->max_vertices = 10; },
           [](SubdivisionOptions* s) { s->max_triangles = 10; }}) {
    SubdivisionOptions other = o;
    change(&other);
    EXPECT_NE(memo.SubdivisionKeyOf(other, triangles), key);
  }
  auto other = triangles;
  other[1] = {0, 3, 2};
  EXPECT_NE(memo.SubdivisionKeyOf(o, other), key);
  other.pop_back();
  EXPECT_NE(memo.SubdivisionKeyOf(o, other), key);
  EXPECT_NE(PlacementMemo(8).SubdivisionKeyOf(o, triangles), key);  // seeded per memo
}

// An entry keeps the last verdict noted for it; it is given for its key
// only, and counted when given.
TEST(PlacementMemo, KeepsTheLastUnrefinedVerdictOfAnEntry) {
  PlacementMemo memo(8);
  const auto a = memo.KeyOf("a", PlacementOptions{}, Square());
  const std::vector<std::array<uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  const auto adaptive = memo.SubdivisionKeyOf(SubdivisionIn(SubdivisionMode::kAdaptive), triangles);
  const auto uniform = memo.SubdivisionKeyOf(SubdivisionIn(SubdivisionMode::kUniform), triangles);
  SubdivisionStats stats;
  stats.measured_points = 17;
  memo.NoteUnrefined(a, adaptive, stats);  // not stored yet: nothing
  memo.Store(a, WithScale(1.0));
  EXPECT_FALSE(memo.Find(a)->unrefined.has_value());
  memo.NoteUnrefined(a, adaptive, stats);
  const auto found = memo.Find(a);
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(memo.UnrefinedVerdict(*found, uniform), nullptr);
  const SubdivisionStats* verdict = memo.UnrefinedVerdict(*found, adaptive);
  ASSERT_NE(verdict, nullptr);
  EXPECT_EQ(verdict->measured_points, 17u);
  EXPECT_EQ(memo.stats().subdivisions_skipped, 1u);

  stats.measured_points = 5;
  memo.NoteUnrefined(a, uniform, stats);
  const auto replaced = memo.Find(a);
  EXPECT_EQ(memo.UnrefinedVerdict(*replaced, adaptive), nullptr);
  ASSERT_NE(memo.UnrefinedVerdict(*replaced, uniform), nullptr);
  EXPECT_EQ(memo.UnrefinedVerdict(*replaced, uniform)->measured_points, 5u);
  EXPECT_EQ(memo.stats().subdivisions_skipped, 3u);
}

TEST(PlacementMemo, ZeroCapacityStoresNothing) {
  PlacementMemo memo(0);
  const auto a = memo.KeyOf("a", PlacementOptions{}, Square());
  memo.Store(a, WithScale(2.0));
  EXPECT_FALSE(memo.Find(a).has_value());
  EXPECT_EQ(memo.stats().entries, 0u);
}

std::shared_ptr<const SheetFootprint> FootprintOf(size_t vertices) {
  auto f = std::make_shared<SheetFootprint>();
  f->location.resize(vertices);
  return f;
}

// Footprints are kept within the byte budget, the least recently used
// dropped first (their placements stay); one larger than a quarter of the
// budget is not kept; an entry stored without one gains it later.
TEST(PlacementMemo, FootprintsStayWithinTheByteBudget) {
  constexpr size_t kBytes = 100 * sizeof(SheetLocation);
  PlacementMemo memo(8, 4 * kBytes);
  const PlacementOptions o;
  std::vector<PlacementMemo::Key> keys;
  for (const char* id : {"a", "b", "c", "d", "e"}) keys.push_back(memo.KeyOf(id, o, Square()));
  for (int k = 0; k < 4; ++k) memo.Store(keys[k], WithScale(k), FootprintOf(100));
  EXPECT_EQ(memo.stats().footprints, 4u);
  EXPECT_EQ(memo.stats().footprint_bytes, 4 * kBytes);
  ASSERT_TRUE(memo.Find(keys[0]).has_value());          // a becomes the most recent
  memo.Store(keys[4], WithScale(4), FootprintOf(100));  // drops b's footprint
  EXPECT_EQ(memo.stats().footprint_bytes, 4 * kBytes);
  const auto b = memo.Find(keys[1]);
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->placement.scale, 1.0);
  EXPECT_EQ(b->footprint, nullptr);
  for (int k : {0, 2, 3, 4}) {
    const auto e = memo.Find(keys[k]);
    ASSERT_TRUE(e.has_value());
    ASSERT_NE(e->footprint, nullptr) << k;
    EXPECT_EQ(e->footprint->location.size(), 100u);
  }

  PlacementMemo small(8, 4 * kBytes);
  small.Store(keys[0], WithScale(1), FootprintOf(101));  // over a quarter: not kept
  EXPECT_EQ(small.Find(keys[0])->footprint, nullptr);
  small.Store(keys[0], WithScale(9), FootprintOf(50));  // gained; the placement stays
  const auto a = small.Find(keys[0]);
  ASSERT_NE(a->footprint, nullptr);
  EXPECT_EQ(a->placement.scale, 1.0);
  EXPECT_EQ(small.stats().footprint_bytes, 50 * sizeof(SheetLocation));

  PlacementMemo none(8);  // no budget: placements only
  none.Store(keys[0], WithScale(1), FootprintOf(1));
  EXPECT_EQ(none.Find(keys[0])->footprint, nullptr);
  EXPECT_EQ(none.stats().footprint_bytes, 0u);
}

// Entries dropped past the capacity give their footprint's bytes back.
TEST(PlacementMemo, DroppedEntriesReleaseTheirFootprints) {
  PlacementMemo memo(2, 1 << 20);
  const PlacementOptions o;
  for (const char* id : {"a", "b", "c"}) {
    memo.Store(memo.KeyOf(id, o, Square()), WithScale(1), FootprintOf(10));
  }
  EXPECT_EQ(memo.stats().entries, 2u);
  EXPECT_EQ(memo.stats().footprints, 2u);
  EXPECT_EQ(memo.stats().footprint_bytes, 20 * sizeof(SheetLocation));
}

}  // namespace
}  // namespace surfdeform
