// The service's memo of placements: keys that tell models, surfaces and
// options apart, and a bounded least-recently-used store.
#include "service/placement_memo.hpp"

#include <gtest/gtest.h>

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
  EXPECT_EQ(memo.Find(a)->scale, 1.5);
  memo.Store(c, WithScale(3.5));  // drops b, the least recently used
  EXPECT_FALSE(memo.Find(b).has_value());
  ASSERT_TRUE(memo.Find(c).has_value());
  EXPECT_EQ(memo.Find(c)->scale, 3.5);
  memo.Store(c, WithScale(9.0));  // stored again by a concurrent request: kept as it was
  EXPECT_EQ(memo.Find(c)->scale, 3.5);

  const PlacementMemoStats stats = memo.stats();
  EXPECT_EQ(stats.entries, 2u);
  EXPECT_EQ(stats.capacity, 2u);
  EXPECT_EQ(stats.hits, 5u);
  EXPECT_EQ(stats.misses, 2u);
}

TEST(PlacementMemo, ZeroCapacityStoresNothing) {
  PlacementMemo memo(0);
  const auto a = memo.KeyOf("a", PlacementOptions{}, Square());
  memo.Store(a, WithScale(2.0));
  EXPECT_FALSE(memo.Find(a).has_value());
  EXPECT_EQ(memo.stats().entries, 0u);
}

}  // namespace
}  // namespace surfdeform
