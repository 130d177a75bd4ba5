#include "proto/map_api.hpp"

#include <cmath>

#include "proto/json_object.hpp"

namespace surfdeform::proto {
namespace {

using nlohmann::json;

template <typename V>
Status ReadPointList(const json& value, const std::string& path, int dims, std::vector<V>* out) {
  if (!value.is_array()) {
    return Malformed("must be an array of " + std::string(dims == 2 ? "[x, y]" : "[x, y, z]") +
                         " points, got " + JsonTypeName(value),
                     path);
  }
  out->clear();
  out->reserve(value.size());
  for (size_t k = 0; k < value.size(); ++k) {
    V p;
    if constexpr (V::RowsAtCompileTime == 2) {
      SURFDEFORM_RETURN_IF_ERROR(ReadVec2(value[k], JoinPath(path, k), &p));
    } else {
      SURFDEFORM_RETURN_IF_ERROR(ReadVec3(value[k], JoinPath(path, k), &p));
    }
    if (!p.allFinite()) return InvalidArgument("must be finite", JoinPath(path, k));
    out->push_back(p);
  }
  return Status::Ok();
}

Status CheckCount(size_t count, size_t limit, const std::string& field, const char* what) {
  if (count <= limit) return Status::Ok();
  return Status::LimitExceeded(
      std::to_string(count) + " " + what + " in one request; at most " + std::to_string(limit),
      field, static_cast<double>(limit), static_cast<double>(count));
}

json Vec(const Vec2& v) { return {v.x(), v.y()}; }
json Vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

json MarkJson(const SheetMark& m, bool with_distance) {
  json j = {{"point", Vec(m.point)},
            {"normal", Vec(m.normal)},
            {"uv", Vec(m.uv)},
            {"sheet", Vec(m.sheet)},
            {"on_sheet", m.on_sheet}};
  if (with_distance) j["distance"] = m.distance;
  return j;
}

}  // namespace

Result<MapRequest> ParseMapRequest(const json& body, const MapLimits& limits) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto o, JsonObject::Open(body, ""));
  MapRequest r;
  const json* points = o.Find("points");
  const json* polylines = o.Find("polylines");
  const json* surface_points = o.Find("surface_points");
  const int given = (points != nullptr) + (polylines != nullptr) + (surface_points != nullptr);
  if (given != 1) {
    return Malformed(
        "name exactly one of \"points\" (sheet points), \"polylines\" (sheet polylines) and "
        "\"surface_points\" (points in space), got " +
            std::to_string(given),
        given == 0 ? "points" : "polylines");
  }
  if (points != nullptr) {
    r.kind = MapRequest::Kind::kPoints;
    SURFDEFORM_RETURN_IF_ERROR(ReadPointList(*points, "points", 2, &r.points));
    SURFDEFORM_RETURN_IF_ERROR(CheckCount(r.points.size(), limits.max_points, "points", "points"));
  } else if (surface_points != nullptr) {
    r.kind = MapRequest::Kind::kSurfacePoints;
    SURFDEFORM_RETURN_IF_ERROR(
        ReadPointList(*surface_points, "surface_points", 3, &r.surface_points));
    SURFDEFORM_RETURN_IF_ERROR(CheckCount(r.surface_points.size(), limits.max_surface_points,
                                          "surface_points", "surface points"));
  } else {
    r.kind = MapRequest::Kind::kPolylines;
    if (!polylines->is_array()) {
      return Malformed("must be an array of polylines, got " + JsonTypeName(*polylines),
                       "polylines");
    }
    size_t count = 0;
    for (size_t k = 0; k < polylines->size(); ++k) {
      std::vector<Vec2> line;
      SURFDEFORM_RETURN_IF_ERROR(
          ReadPointList((*polylines)[k], JoinPath("polylines", k), 2, &line));
      count += line.size();
      SURFDEFORM_RETURN_IF_ERROR(
          CheckCount(count, limits.max_points, "polylines", "polyline points"));
      r.polylines.push_back(std::move(line));
    }
  }
  for (auto [key, out] : {std::pair{"max_segment", &r.polyline.max_segment},
                          std::pair{"tolerance", &r.polyline.tolerance}}) {
    if (o.Find(key) == nullptr) continue;
    if (polylines == nullptr) return Malformed("only polylines take it", key);
    SURFDEFORM_RETURN_IF_ERROR(o.Number(key, out));
    if (!(*out >= 0.0) || !std::isfinite(*out)) {
      return InvalidArgument("must be a finite number, 0 or more", key);
    }
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return r;
}

json ToJson(const MapRequest& r) {
  auto list = [](const auto& points) {
    json a = json::array();
    for (const auto& p : points) a.push_back(Vec(p));
    return a;
  };
  switch (r.kind) {
    case MapRequest::Kind::kPoints:
      return {{"points", list(r.points)}};
    case MapRequest::Kind::kSurfacePoints:
      return {{"surface_points", list(r.surface_points)}};
    case MapRequest::Kind::kPolylines:
      break;
  }
  json lines = json::array();
  for (const auto& line : r.polylines) lines.push_back(list(line));
  return {{"polylines", std::move(lines)},
          {"max_segment", r.polyline.max_segment},
          {"tolerance", r.polyline.tolerance}};
}

json MapResponseJson(MapRequest::Kind kind, const std::vector<std::vector<SheetMark>>& marks) {
  const bool nearest = kind == MapRequest::Kind::kSurfacePoints;
  auto list = [nearest](const std::vector<SheetMark>& line) {
    json a = json::array();
    for (const SheetMark& m : line) a.push_back(MarkJson(m, nearest));
    return a;
  };
  if (kind == MapRequest::Kind::kPolylines) {
    json all = json::array();
    for (const auto& line : marks) all.push_back(list(line));
    return {{"polylines", std::move(all)}};
  }
  return {{nearest ? "surface_points" : "points", marks.empty() ? json::array() : list(marks[0])}};
}

}  // namespace surfdeform::proto
