// Marks between the flat sheet and the surface (Rhino's SquishBack): where a
// point drawn on the sheet lands on the surface, a polyline drawn on the
// sheet resampled so that its image follows the surface, and, the other way,
// where the surface point nearest to a point in space lies on the sheet.
#pragma once

#include <vector>

#include "base/status.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/sheet/sheet_mark.hpp"

namespace surfdeform {

// The surface under sheet point `ab`; off the sheet, under the nearest point
// of its boundary (on_sheet false; `sheet` stays `ab`).
SheetMark MarkAt(const SheetMap& map, const Vec2& ab);

// A resampling as the engine runs it: the request's settings and the
// service's point limit.
struct PolylineOptions : PolylineSettings {
  size_t max_points = 1000000;  // over all polylines of a call
};

// Each polyline (sheet coordinates, two points or more) with points added
// between its vertices, by bisection, until every piece is at most
// max_segment long on the sheet and the straight chord between the images of
// its ends stays within the tolerance of the image of the piece (tested at
// a quarter, half and three quarters). The given vertices are kept.
// kLimitExceeded past max_points; kInvalidArgument for a non-finite point,
// a polyline of fewer than two points, or a tolerance or max_segment under
// kFinestMarkShare of the sheet's diagonal.
Result<std::vector<std::vector<SheetMark>>> ResamplePolylines(
    const SheetMap& map, const std::vector<std::vector<Vec2>>& polylines,
    const PolylineOptions& options);

// The surface point nearest to `x` (over the surface's whole parameter
// domain [0, 1]^2): the nearest of the sheet's samples, then Newton's method
// on the squared distance, kept inside the domain. `sheet` is its flat point.
SheetMark MarkNearest(const SheetMap& map, const Vec3& x);

}  // namespace surfdeform
