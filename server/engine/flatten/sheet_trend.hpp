// Where a live edit is heading: a person dragging a control point makes a
// run of edits that each move the surface, and so its flat sheet, much as
// the one before did. An edit warm-started from the previous sheet converges
// in fewer iterations still when it starts where the sheet is heading: the
// previous sheet moved on by the previous edit's change of it, scaled by how
// much of that change this edit repeats (a secant step, as the animation's
// frames are extrapolated from the frames before them).
#pragma once

#include <span>
#include <vector>

#include "engine/common/flat_sheet.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform {

// How a sheet changed over the edit that made it: its samples and flat
// positions (canonical frame) minus those of the sheet that edit started
// from, sample for sample. Empty when there is none.
struct SheetTrend {
  std::vector<Vec3> points;
  std::vector<Vec2> flat;

  bool empty() const { return flat.empty(); }
  size_t bytes() const {
    return sizeof(*this) + points.size() * sizeof(Vec3) + flat.size() * sizeof(Vec2);
  }
};

// The change from `before` to `after`: empty unless both are sheets of the
// same grid, neither periodic (a periodic sheet's layout is its period's).
SheetTrend TrendBetween(const FlatSheet& before, const FlatSheet& after);

// How far along `trend` the samples moved from `from` to `now`: the least-
// squares step s minimizing |now - from - s trend.points|, within [-2, 2]
// (negative: the drag turned back). 0 when the trend does not fit them, or
// the samples moved across it.
double TrendStep(const SheetTrend& trend, std::span<const Vec3> from, std::span<const Vec3> now);

// `flat` moved on by `step` times the trend's change of the flat positions.
std::vector<Vec2> Extrapolated(std::span<const Vec2> flat, const SheetTrend& trend, double step);

}  // namespace surfdeform
