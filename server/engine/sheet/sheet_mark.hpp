// A mark between the flat sheet and the surface (POST
// /v1/surfaces/{id}/map): where a sheet point lands, and how a request's
// polylines are resampled. Plain vocabulary, which the API's request types
// (proto/map_api.hpp) share with the engine (sheet_marks.hpp computes them).
#pragma once

#include "engine/common/geometry_types.hpp"

namespace surfdeform {

struct SheetMark {
  Vec3 point = Vec3::Zero();    // on the surface
  Vec3 normal = Vec3::UnitZ();  // unit
  Vec2 uv = Vec2::Zero();       // surface parameters
  Vec2 sheet = Vec2::Zero();    // flat-sheet coordinates
  bool on_sheet = true;         // false: the sheet point was off the sheet (clamped to it)
  double distance = 0.0;        // MarkNearest: from the query point to `point`
};

// The finest tolerance and segment a resampling takes, as a share of the
// sheet's diagonal: the flattening keeps distances to about 1e-6, so finer
// pieces only multiply points (to the output limit, from a request of a
// few bytes).
inline constexpr double kFinestMarkShare = 1e-7;

struct PolylineSettings {
  double max_segment = 0.0;  // > 0: no piece longer than this on the sheet (at least
                             // kFinestMarkShare of its diagonal)
  double tolerance = 0.0;    // > 0: the largest distance of the image's chords from the
                             // surface (at least kFinestMarkShare of the diagonal);
                             // 0 = 1e-3 of the sheet's diagonal
};

}  // namespace surfdeform
