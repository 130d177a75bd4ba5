// floor(v) or ceil(v) as an index or a count of a grid or bucket array, for
// v of any size. A double past int's range converted as it is is undefined
// behaviour: a placement centred at 1e20 on a sheet a few units wide sent
// such values into the bucket searches (found by the estimate fuzzer).
#pragma once

#include <cmath>

namespace surfdeform {

// floor(v) clamped to [lo, hi]; lo for NaN.
inline int ClampedFloor(double v, int lo, int hi) {
  if (!(v >= lo)) return lo;
  if (v >= hi) return hi;
  return static_cast<int>(std::floor(v));
}

// ceil(v) clamped to [lo, hi]; lo for NaN.
inline int ClampedCeil(double v, int lo, int hi) {
  if (!(v > lo)) return lo;
  if (v > hi) return hi;
  return static_cast<int>(std::ceil(v));
}

}  // namespace surfdeform
