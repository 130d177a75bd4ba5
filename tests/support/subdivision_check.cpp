#include "support/subdivision_check.hpp"

#include "support/expect_ok.hpp"

#include "engine/sheet/sheet_map.hpp"

namespace surfdeform::testing {

Refined Refine(const Target& t, const Mesh& m, const PlacementOptions& o,
               const SubdivisionOptions& s) {
  Refined r;
  const SheetMap map(*t.surface, t.sheet);
  auto pl = ComputePlacement(map, m.positions, o);
  ExpectOk(pl);
  if (!pl.ok()) return r;
  std::vector<Vec3> placed;
  for (const Vec3& p : m.positions) placed.push_back(pl->Apply(p));
  // As the deformation asks: the input's positions when it has no frame to carry.
  const InputPositions want = m.normals.empty() && m.tangents.empty() ? InputPositions::kWanted
                                                                      : InputPositions::kNotWanted;
  auto sub = Subdivide(m, placed, map, o.outside, s, want);
  ExpectOk(sub);
  if (!sub.ok()) return r;
  r.model = sub->unchanged ? m : std::move(sub->mesh);
  r.placed = sub->unchanged ? placed : std::move(sub->placed);
  r.stats = sub->stats;
  int hint = -1;
  for (const Vec3& p : r.placed) r.deformed.push_back(map.Position(p, o.outside, &hint));
  r.ok = true;
  return r;
}

// The largest distance, at 28 points per triangle (a barycentric lattice of
// step 1/6, corners excluded), between the refined mesh's deformed triangles
// and the exact deformation of the model points they stand for.
double DenseDeviation(const Target& t, const Refined& r, OutsideMode outside) {
  const SheetMap map(*t.surface, t.sheet);
  double worst = 0.0;
  int hint = -1;
  for (const auto& tri : r.model.triangles) {
    for (int i = 0; i <= 6; ++i) {
      for (int j = 0; i + j <= 6; ++j) {
        const double l1 = i / 6.0, l2 = j / 6.0, l0 = 1.0 - l1 - l2;
        if (l0 == 1.0 || l1 == 1.0 || l2 == 1.0) continue;
        const Vec3 placed = l0 * r.placed[tri[0]] + l1 * r.placed[tri[1]] + l2 * r.placed[tri[2]];
        const Vec3 linear =
            l0 * r.deformed[tri[0]] + l1 * r.deformed[tri[1]] + l2 * r.deformed[tri[2]];
        worst = std::max(worst, (map.Position(placed, outside, &hint) - linear).norm());
      }
    }
  }
  return worst;
}

}  // namespace surfdeform::testing
