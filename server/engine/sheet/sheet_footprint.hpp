// Where a model's vertices lie on a sheet: the first half of the map, kept
// for a model that comes back.
//
// Locating a vertex (finding its sheet cell, inverting the cell's bilinear
// map) is most of the map's cost when no subdivision runs. It depends only on
// the vertex's placed point and the sheet, so a caller that deforms the same
// model with the same placement on the same sheet again (a load test, a
// viewer trying subdivisions or formats) can keep the locations of the first
// deformation and give them to the next: the result is the same, bit for
// bit, without the search. Points off the sheet are not kept (they are
// located again each time: their parameters depend on the outside mode).
#pragma once

#include <cstddef>
#include <vector>

#include "engine/sheet/sheet_map.hpp"

namespace surfdeform {

struct SheetFootprint {
  // Per input vertex: its location on the sheet; i < 0 where it is off the
  // sheet or was not located on a cell (sheets unrolled in closed form).
  std::vector<SheetLocation> location;

  size_t bytes() const { return location.capacity() * sizeof(SheetLocation); }
};

// How one deformation uses footprints: `known` from an earlier one (read),
// `record` to fill for later ones (its locations are written by vertex, so
// threads may share it). Both may be null.
struct FootprintUse {
  const SheetFootprint* known = nullptr;
  SheetFootprint* record = nullptr;

  // SheetMap::Parameters of input vertex k at flat point `ab`, from `known`
  // when it holds the vertex.
  SheetParameters Parameters(const SheetMap& map, size_t k, const Vec2& ab, OutsideMode outside,
                             bool want_jacobian, int* hint) const {
    if (known != nullptr && known->location[k].i >= 0) {
      return map.ParametersAt(known->location[k], want_jacobian);
    }
    SheetParameters p = map.Parameters(ab, outside, want_jacobian, hint);
    if (record != nullptr) {
      SheetLocation& l = record->location[k];
      l = p.location;
      if (p.cell < 0) l.i = -1;
    }
    return p;
  }
};

}  // namespace surfdeform
