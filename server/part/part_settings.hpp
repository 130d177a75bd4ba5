// A part's request as the API states it: the body's thickness and side, and
// the printer's limits. Vocabulary shared with proto (no geometry).
#pragma once

#include "base/enum_table.hpp"

namespace surfdeform {

// Where the material lies against the surface's normal: along it, against
// it, or half each way. The surface itself is a face of the part, except
// with kBoth.
enum class BodySide { kOutside, kInside, kBoth };
inline constexpr EnumEntry<BodySide> kBodySides[] = {
    {BodySide::kOutside, "outside", "the material lies along the surface's normal"},
    {BodySide::kInside, "inside", "the material lies against the surface's normal"},
    {BodySide::kBoth, "both", "half the thickness each way"},
};

// The thickest body a request may ask for, mm.
inline constexpr double kMaxBodyThicknessMm = 1000.0;

struct PartSettings {
  double thickness_mm = 1.0;
  BodySide side = BodySide::kOutside;
  // The printer's limits, checked on the result: walls thinner than
  // min_wall_mm are a warning (with strict, a 422). 0: not checked.
  double min_wall_mm = 0.0;
  double min_detail_mm = 0.0;
  bool strict = false;
};

}  // namespace surfdeform
