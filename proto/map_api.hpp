// POST /v1/surfaces/{id}/map: marks between the flat sheet and the surface.
// The request names exactly one of
//   "points":         [[x, y], ...]  sheet points -> where they land;
//   "polylines":      [[[x, y], ...], ...], with optional "max_segment" and
//                     "tolerance": each resampled so that its image follows
//                     the surface (engine/sheet_marks.hpp);
//   "surface_points": [[x, y, z], ...] -> the nearest surface points.
// The answer has the same key, with a mark per point:
//   {"point", "normal", "uv", "sheet", "on_sheet"} (and "distance" for
//   surface_points).
#pragma once

#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

#include "base/status.hpp"
#include "engine/sheet/sheet_mark.hpp"

namespace surfdeform::proto {

struct MapRequest {
  enum class Kind { kPoints, kPolylines, kSurfacePoints };
  Kind kind = Kind::kPoints;
  std::vector<Vec2> points;
  std::vector<std::vector<Vec2>> polylines;
  std::vector<Vec3> surface_points;
  PolylineSettings polyline;
};

struct MapLimits {
  size_t max_points = 100'000;         // points, or polyline vertices, in a request
  size_t max_surface_points = 10'000;  // nearest-point queries in a request
};

// kMalformed for a wrong shape or type (naming the JSON path), for none or
// more than one of the three keys, and for max_segment or tolerance without
// polylines; kInvalidArgument for a negative or non-finite number;
// kLimitExceeded past the limits (with the limit and the count).
Result<MapRequest> ParseMapRequest(const nlohmann::json& body, const MapLimits& limits);

// The request as JSON, which ParseMapRequest reads back into the same
// request (the client builds its requests with it): max_segment and
// tolerance with polylines only, 0 when not given.
nlohmann::json ToJson(const MapRequest& request);

// The limits a client reads a request with: none (the server's are its own
// to apply, at /v1/info).
inline constexpr MapLimits kNoMapLimits{std::numeric_limits<size_t>::max(),
                                        std::numeric_limits<size_t>::max()};

// The answer: {"<kind>": [mark, ...]} or, for polylines, [[mark, ...], ...].
nlohmann::json MapResponseJson(const MapRequest::Kind kind,
                               const std::vector<std::vector<SheetMark>>& marks);

}  // namespace surfdeform::proto
