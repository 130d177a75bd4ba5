// The sheet-to-surface map sampled on a regular lattice over the flat
// sheet's bounding box: the surface point and unit normal under each lattice
// point, and whether the point lies on the sheet. Points off the sheet carry
// the map continued from the nearest boundary cell (OutsideMode::
// kExtrapolate), so that interpolating between lattice points stays smooth
// up to and across the sheet's border.
//
// It is what a client needs to preview a deformation itself, on a GPU:
// F(a, b, h) ~ P(a, b) + h N(a, b), with P and N interpolated bilinearly
// between lattice points (the exact map is SheetMap's).
#pragma once

#include <cstdint>
#include <vector>

#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"
#include "engine/sheet/sheet_map.hpp"

namespace surfdeform {

inline constexpr int kMinFieldSide = 2;

struct SheetField {
  int n = 0;                      // lattice points per side
  Vec2 lo = Vec2::Zero();         // the sheet's bounding box: lattice point (0, 0) ...
  Vec2 hi = Vec2::Zero();         // ... and (n - 1, n - 1)
  std::vector<Vec3> positions;    // n * n, index i + n * j (x varies fastest)
  std::vector<Vec3> normals;      // unit
  std::vector<uint8_t> on_sheet;  // 1 where the lattice point lies on the sheet
  // The surface parameters (u, v) each point was evaluated at (continued past
  // [0, 1] off the sheet): with them a client moves the field with an edit of
  // a surface that is linear in its control points (a Bezier patch), before
  // the edit's own field comes.
  std::vector<Vec2> params;
};

// The field of `map` with n x n lattice points, lattice point (i, j) at
// lo + (i (hi.x - lo.x) / (n - 1), j (hi.y - lo.y) / (n - 1)). Errors:
// kInvalidArgument for n < kMinFieldSide (field "n"). Results do not depend
// on `threads` (0: one per core).
Result<SheetField> SampleSheetField(const SheetMap& map, int n, int threads = 0);

}  // namespace surfdeform
