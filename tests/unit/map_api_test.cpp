// POST /v1/surfaces/{id}/map's JSON: the three request forms, the errors
// that name their field, the limits, and the answer's shape.
#include "proto/map_api.hpp"

#include <gtest/gtest.h>

namespace surfdeform::proto {
namespace {

using nlohmann::json;

Status ErrorOf(const json& body, const MapLimits& limits = {}) {
  auto r = ParseMapRequest(body, limits);
  return r.ok() ? Status::Ok() : r.status();
}

TEST(MapApi, ReadsEachForm) {
  auto points = ParseMapRequest(json::parse(R"({"points": [[1, 2], [3.5, -4]]})"), {});
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  EXPECT_EQ(points->kind, MapRequest::Kind::kPoints);
  EXPECT_EQ(points->points, (std::vector<Vec2>{Vec2(1, 2), Vec2(3.5, -4)}));
  auto lines =
      ParseMapRequest(json::parse(R"({"polylines": [[[0, 0], [1, 0]], [[2, 2], [3, 3], [4, 2]]],
                      "max_segment": 0.25, "tolerance": 0.001})"),
                      {});
  ASSERT_TRUE(lines.ok()) << lines.status().ToString();
  EXPECT_EQ(lines->kind, MapRequest::Kind::kPolylines);
  ASSERT_EQ(lines->polylines.size(), 2u);
  EXPECT_EQ(lines->polylines[1][2], Vec2(4, 2));
  EXPECT_EQ(lines->polyline.max_segment, 0.25);
  EXPECT_EQ(lines->polyline.tolerance, 0.001);
  auto near = ParseMapRequest(json::parse(R"({"surface_points": [[1, 2, 3]]})"), {});
  ASSERT_TRUE(near.ok());
  EXPECT_EQ(near->surface_points, (std::vector<Vec3>{Vec3(1, 2, 3)}));
}

TEST(MapApi, ErrorsNameTheirField) {
  struct Case {
    const char* body;
    ErrorCode code;
    const char* field;
  } cases[] = {
      {R"({})", ErrorCode::kMalformed, "points"},
      {R"({"points": [[0, 0]], "surface_points": [[0, 0, 0]]})", ErrorCode::kMalformed,
       "polylines"},
      {R"({"points": [[0, 0], [1]]})", ErrorCode::kMalformed, "points[1]"},
      {R"({"points": [[0, "a"]]})", ErrorCode::kMalformed, "points[0][1]"},
      {R"({"polylines": [[[0, 0], [1, 1]], [[0, 0, 0]]]})", ErrorCode::kMalformed,
       "polylines[1][0]"},
      {R"({"polylines": {"a": 1}})", ErrorCode::kMalformed, "polylines"},
      {R"({"surface_points": [[0, 0]]})", ErrorCode::kMalformed, "surface_points[0]"},
      {R"({"points": [[0, 0]], "max_segment": 1})", ErrorCode::kMalformed, "max_segment"},
      {R"({"polylines": [[[0, 0], [1, 1]]], "tolerance": -1})", ErrorCode::kInvalidArgument,
       "tolerance"},
      {R"({"points": [[0, 0]], "pionts": []})", ErrorCode::kMalformed, "pionts"},
  };
  for (const Case& c : cases) {
    const Status s = ErrorOf(json::parse(c.body));
    EXPECT_EQ(s.code(), c.code) << c.body << ": " << s.ToString();
    EXPECT_EQ(s.field(), c.field) << c.body << ": " << s.ToString();
  }
}

TEST(MapApi, LimitsSayTheLimitAndTheCount) {
  MapLimits limits;
  limits.max_points = 3;
  limits.max_surface_points = 1;
  const Status points = ErrorOf(json::parse(R"({"points": [[0,0],[0,0],[0,0],[0,0]]})"), limits);
  EXPECT_EQ(points.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(points.limit(), 3.0);
  EXPECT_EQ(points.actual(), 4.0);
  const Status lines =
      ErrorOf(json::parse(R"({"polylines": [[[0,0],[1,1]], [[0,0],[1,1]]]})"), limits);
  EXPECT_EQ(lines.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(lines.field(), "polylines");
  const Status near = ErrorOf(json::parse(R"({"surface_points": [[0,0,0],[1,1,1]]})"), limits);
  EXPECT_EQ(near.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(near.actual(), 2.0);
  EXPECT_TRUE(ErrorOf(json::parse(R"({"points": [[0,0],[0,0],[0,0]]})"), limits).ok());
}

// Each form, written by ToJson, reads back into a request that writes the
// same, holding what was given.
TEST(MapApi, WrittenRequestsReadBackTheSame) {
  const char* forms[] = {
      R"({"points": [[1, 2], [3.5, -4]]})",
      R"({"surface_points": [[1, 2, 3], [-0.5, 0, 1e-3]]})",
      R"({"polylines": [[[0, 0], [1, 0]], [[2, 2], [3, 3], [4, 2]]], "max_segment": 0.25,
          "tolerance": 0.001})",
  };
  for (const char* text : forms) {
    SCOPED_TRACE(text);
    const json given = json::parse(text);
    auto r = ParseMapRequest(given, kNoMapLimits);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    const json written = ToJson(*r);
    for (const auto& [key, value] : given.items()) EXPECT_EQ(written.at(key), value) << key;
    auto again = ParseMapRequest(json::parse(written.dump()), kNoMapLimits);
    ASSERT_TRUE(again.ok()) << again.status().ToString();
    EXPECT_EQ(ToJson(*again), written);
  }
}

TEST(MapApi, TheAnswerHasTheRequestsKey) {
  SheetMark m;
  m.point = Vec3(1, 2, 3);
  m.sheet = Vec2(4, 5);
  m.on_sheet = false;
  m.distance = 0.5;
  const json points = MapResponseJson(MapRequest::Kind::kPoints, {{m, m}});
  ASSERT_EQ(points["points"].size(), 2u);
  EXPECT_EQ(points["points"][0]["point"], json::parse("[1.0, 2.0, 3.0]"));
  EXPECT_EQ(points["points"][0]["sheet"], json::parse("[4.0, 5.0]"));
  EXPECT_EQ(points["points"][0]["on_sheet"], false);
  EXPECT_FALSE(points["points"][0].contains("distance"));
  const json near = MapResponseJson(MapRequest::Kind::kSurfacePoints, {{m}});
  EXPECT_EQ(near["surface_points"][0]["distance"], 0.5);
  const json lines = MapResponseJson(MapRequest::Kind::kPolylines, {{m}, {m, m, m}});
  ASSERT_EQ(lines["polylines"].size(), 2u);
  EXPECT_EQ(lines["polylines"][1].size(), 3u);
}

}  // namespace
}  // namespace surfdeform::proto
