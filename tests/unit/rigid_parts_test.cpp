// Rigid parts: a word of box glyphs on a cylinder keeps each glyph's shape
// while the glyphs follow the wrap; components and groups; the corners' lift.
#include "engine/deform/rigid_parts.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/deform/deform.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

using testing::Flattened;
using testing::KeepCoordinates;
using testing::Target;

// Five box glyphs 0.3 wide, 0.4 high, 0.05 thick, 0.1 apart along x, one
// mesh group each.
Mesh Word() {
  Mesh word;
  for (int g = 0; g < 5; ++g) {
    const Mesh box = testing::ThinPlate(0.3, 0.4, 0.05);
    const uint32_t base = static_cast<uint32_t>(word.positions.size());
    const uint32_t first = static_cast<uint32_t>(word.triangles.size());
    for (const Vec3& p : box.positions) word.positions.push_back(p + Vec3(0.4 * (g - 2), 0, 0));
    for (auto t : box.triangles) word.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    word.groups.push_back(
        {"glyph" + std::to_string(g), -1, first, static_cast<uint32_t>(box.triangles.size())});
  }
  return word;
}

TEST(RigidParts, ComponentsAndGroups) {
  const Mesh word = Word();
  int count = 0;
  const std::vector<int> components = RigidParts(word, RigidMode::kComponents, &count);
  EXPECT_EQ(count, 5);
  for (size_t k = 0; k < word.positions.size(); ++k)
    EXPECT_EQ(components[k], static_cast<int>(k / 8));
  EXPECT_EQ(RigidParts(word, RigidMode::kGroups, &count), components);
  EXPECT_EQ(count, 5);
  // Welding by position: a split copy of a vertex joins its component.
  Mesh split = testing::ThinPlate(1.0, 1.0, 0.1);
  split.positions.push_back(split.positions[0]);  // a duplicate, in no triangle of its own...
  split.triangles.push_back({8, 1, 2});           // ... that a triangle uses
  split.positions.push_back(Vec3(5, 5, 5));       // a stray vertex: a part of its own
  RigidParts(split, RigidMode::kComponents, &count);
  EXPECT_EQ(count, 2);
}

TEST(RigidParts, AWordOnACylinderKeepsEachGlyphAndFollowsTheWrap) {
  const double radius = 2.0;
  const Target t = Flattened(CylinderSpec{radius, 3.0, 180.0, {}}, 16);
  const Mesh word = Word();
  const Vec2 at(std::numbers::pi * radius / 2, 1.5);
  PlacementOptions o = KeepCoordinates(word, at);  // (a, b, h) = (x + at.x, y + at.y, z)
  o.rigid = RigidMode::kComponents;
  auto r = Deform(SheetMap(*t.surface, t.sheet), word, {.placement = o});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const Mesh& out = r->mesh;
  EXPECT_EQ(r->stats.rigid.parts, 5u);
  double longest = 0.0;
  for (int g = 0; g < 5; ++g) {
    // Every pairwise distance of the glyph, to 1e-9 relative.
    Vec3 centroid = Vec3::Zero();
    for (int i = 0; i < 8; ++i) {
      centroid += out.positions[8 * g + i] / 8;
      for (int j = i + 1; j < 8; ++j) {
        const double before = (word.positions[8 * g + i] - word.positions[8 * g + j]).norm();
        const double after = (out.positions[8 * g + i] - out.positions[8 * g + j]).norm();
        EXPECT_NEAR(after, before, 1e-9 * before) << g << " " << i << " " << j;
        longest = std::max(longest, before);
      }
    }
    // Its centre on the analytic wrap: the flat centre (a, b) at angle a / R, z = b.
    const double a = at.x() + 0.4 * (g - 2), theta = a / radius;
    EXPECT_LT((centroid - Vec3(radius * std::cos(theta), radius * std::sin(theta), at.y())).norm(),
              1e-9)
        << g;
    // Its up axis (the box's +z edge) along the normal there.
    const Vec3 up = (out.positions[8 * g + 4] - out.positions[8 * g + 0]).normalized();
    EXPECT_LT((up - Vec3(std::cos(theta), std::sin(theta), 0)).norm(), 1e-9) << g;
    // Its corners stand off the curve: the sagitta of half its width.
    const double half = 0.15 / radius;
    const double lift = radius * std::cos(half) + 0.15 * std::sin(half) - radius;
    EXPECT_NEAR(r->stats.rigid.each[g].lift, lift, 1e-9) << g;
    EXPECT_NEAR(r->stats.rigid.each[g].sink, 0.0, 1e-12) << g;
  }
  EXPECT_NEAR(r->stats.rigid.max_lift, radius * std::cos(0.075) + 0.15 * std::sin(0.075) - radius,
              1e-9);
  // Without rigid parts the glyphs bend: their distances change (the test is not vacuous).
  o.rigid = RigidMode::kNone;
  auto bent = Deform(SheetMap(*t.surface, t.sheet), word, {.placement = o});
  ASSERT_TRUE(bent.ok());
  double change = 0.0;
  for (int i = 0; i < 8; ++i)
    for (int j = i + 1; j < 8; ++j)
      change =
          std::max(change, std::abs((bent->mesh.positions[i] - bent->mesh.positions[j]).norm() -
                                    (word.positions[i] - word.positions[j]).norm()));
  EXPECT_GT(change, 1e-4);
}

TEST(RigidParts, NormalsTurnWithTheirPartAndOffSheetPartsAreCounted) {
  const Target t = Flattened(CylinderSpec{2.0, 3.0, 180.0, {}}, 16);
  Mesh grid = testing::FlatGrid(-0.2, -0.2, 0.4, 0.4, 2, 2, 0.0);  // normals +Z
  PlacementOptions o = KeepCoordinates(grid, Vec2(1.0, 1.5));
  o.rigid = RigidMode::kGroups;
  auto r = Deform(SheetMap(*t.surface, t.sheet), grid, {.placement = o});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const double theta = 1.0 / 2.0;
  for (const Vec3& n : r->mesh.normals) {
    EXPECT_LT((n - Vec3(std::cos(theta), std::sin(theta), 0)).norm(), 1e-9);
  }
  // Centred off the sheet: an error that counts its vertices.
  o = KeepCoordinates(grid, Vec2(1.0, 4.0));
  o.rigid = RigidMode::kGroups;
  auto off = Deform(SheetMap(*t.surface, t.sheet), grid, {.placement = o});
  ASSERT_FALSE(off.ok());
  EXPECT_EQ(off.status().code(), ErrorCode::kOutsideSheet);
}

}  // namespace
}  // namespace surfdeform
