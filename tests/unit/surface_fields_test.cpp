// One description of each surface kind's fields (engine/surface_fields.hpp):
// a kind with a field added is read, written, walked (interpolated and
// bounded) and counted by the same code that serves every real kind.
#include <gtest/gtest.h>

#include <concepts>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/surface/surface_fields.hpp"
#include "proto/api.hpp"
#include "proto/json_object.hpp"
#include "proto/surface_json.hpp"
#include "support/surface_file.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;

// A kind of the test's own, with one field of every sort; `added` is the
// field a new feature would add.
struct TestKind {
  int count = 0;
  double radius = 1.0;
  double added = 0.0;
  std::vector<Vec3> points;
  std::vector<double> knots;
  bool closed = false;
  Frame frame;
  std::string id;
};

template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, TestKind>
void VisitFields(S& s, V&& v) {
  v.Integer("count", s.count);
  v.Number("radius", s.radius);
  v.Number("added", s.added);
  v.Points("points", s.points);
  v.Numbers("knots", s.knots);
  v.Flag("closed", s.closed);
  v.Placement("frame", s.frame);
  v.Text("id", s.id);
}

const json kGiven = {{"count", 2},
                     {"radius", 1.5},
                     {"added", 7.25},
                     {"points", {{1, 2, 3}}},
                     {"knots", {0, 1}},
                     {"closed", true},
                     {"frame", {{"origin", {1, 0, 0}}}},
                     {"id", "abc"}};

TEST(SurfaceFields, AFieldAddedToAKindIsReadWrittenAndWalked) {
  auto o = proto::JsonObject::Open(kGiven, "surface");
  ASSERT_TRUE(o.ok());
  TestKind k;
  ASSERT_TRUE(proto::ReadFields(*o, k).ok());
  EXPECT_TRUE(o->Finish().ok()) << "every key read, the added one too";
  EXPECT_EQ(k.added, 7.25);
  EXPECT_EQ(k.count, 2);
  EXPECT_TRUE(k.closed);
  EXPECT_EQ(k.frame.origin, Vec3(1, 0, 0));
  EXPECT_EQ(k.id, "abc");

  json written;
  proto::WriteFields(k, &written);
  json expected = kGiven;
  expected["frame"] = {{"origin", {1, 0, 0}}, {"x_axis", {1, 0, 0}}, {"z_axis", {0, 0, 1}}};
  EXPECT_EQ(written, expected);

  std::vector<std::string> names;
  std::vector<double> values;
  WalkFields(k, [&](const auto& name, double& v) {
    names.push_back(name());
    values.push_back(v);
  });
  const std::vector<std::string> walked = {
      "radius",          "added",           "points[0][0]",    "points[0][1]",
      "points[0][2]",    "knots[0]",        "knots[1]",        "frame.origin[0]",
      "frame.origin[1]", "frame.origin[2]", "frame.x_axis[0]", "frame.x_axis[1]",
      "frame.x_axis[2]", "frame.z_axis[0]", "frame.z_axis[1]", "frame.z_axis[2]"};
  EXPECT_EQ(names, walked);
  EXPECT_EQ(values[1], 7.25);
}

TEST(SurfaceFields, AKeyNoKindListsIsRefusedWhereItIs) {
  json given = kGiven;
  given["other"] = 1;
  auto o = proto::JsonObject::Open(given, "surface");
  ASSERT_TRUE(o.ok());
  TestKind k;
  ASSERT_TRUE(proto::ReadFields(*o, k).ok());
  const Status s = o->Finish();
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.field(), "surface.other");
}

TEST(SurfaceFields, TheFirstBadFieldIsTheErrorAndNothingAfterItIsRead) {
  json given = kGiven;
  given["added"] = "seven";
  given["knots"] = "none";
  auto o = proto::JsonObject::Open(given, "surface");
  ASSERT_TRUE(o.ok());
  TestKind k;
  const Status s = proto::ReadFields(*o, k);
  EXPECT_EQ(s.field(), "surface.added");
  EXPECT_TRUE(k.points.empty());  // after the bad field
}

TEST(SurfaceFields, EveryRealKindCountsWhatItWalks) {
  const SurfaceSpec specs[] = {BezierSpec{3, 3, std::vector<Vec3>(16, Vec3::Zero())},
                               CylinderSpec{},
                               ConeSpec{},
                               SphereSpec{},
                               TorusSpec{},
                               WaveSpec{},
                               MeshSpec{}};
  const size_t expected[] = {48, 12, 13, 14, 15, 15, 0};
  for (size_t k = 0; k < std::size(specs); ++k) {
    EXPECT_EQ(CountNumbers(specs[k]), expected[k]) << k;
  }
}

// Content ids are how replicas of different releases share surfaces
// (Redis) and clients keep them: a request's id must not change when the
// code that reads and writes it does. These were computed by the release
// before the fields' description (d2e0d0c, POST /v1/surfaces at 16 x 16),
// one request of every kind.
TEST(SurfaceFields, IdsOfEveryKindStayAsTheReleaseBeforeGaveThem) {
  const std::string cp =
      R"([[0,0,0],[1,0,0],[2,0,0],[0,1,0],[1,1,0.3],[2,1,0],[0,2,0],[1,2,0],[2,2,0]])";
  const std::string knots = R"("knots_u":[0,0,0,1,1,1],"knots_v":[0,0,0,1,1,1])";
  const std::string spline =
      R"("degree_u":2,"degree_v":2,"count_u":3,"count_v":3,"control_points":)" + cp + "," + knots;
  const std::pair<std::string, std::string> cases[] = {
      {R"({"kind":"bspline",)" + spline + "}", "39217d5119f0cc9c71445cc0cdc83b9b"},
      {R"({"kind":"nurbs",)" + spline + R"(,"weights":[1,1,1,1,2,1,1,1,1]})",
       "c1089c52ff009803a3f34f48ca369fe2"},
      {R"({"kind":"bspline",)" + spline + R"(,"periodic_v":false})",
       "39217d5119f0cc9c71445cc0cdc83b9b"},
      {R"({"kind":"cylinder","radius":1,"height":2,"angle_deg":180,)"
       R"("frame":{"origin":[0.5,0,0],"x_axis":[0,1,0],"z_axis":[0,0,1]}})",
       "e37be5dbed953f06d7c93aee60c14f4f"},
      {R"({"kind":"cone","radius_bottom":1,"radius_top":0.5,"height":1,"angle_deg":180})",
       "c338c54b84324ee0f80bf122513d2aae"},
      {R"({"kind":"sphere","radius":1,"lon_min_deg":0,"lon_max_deg":90,"lat_min_deg":-30,)"
       R"("lat_max_deg":30})",
       "9b5f8543764dbdd3e3f4fdd016e7f58c"},
      {R"({"kind":"torus","major_radius":2,"minor_radius":0.5,"u_min_deg":0,"u_max_deg":90,)"
       R"("v_min_deg":-90,"v_max_deg":90})",
       "eb73116c42af308b491fba10a2948c47"},
      {R"({"kind":"wave","length":4,"width":1,"amplitude":0.2,"wavelength":2,"speed":1,)"
       R"("time":0.3})",
       "6a9798912b73579f1a154f074f0a336e"},
      {R"({"kind":"grid","nu":3,"nv":3,"points":)" + cp + "}", "f67e9594fe5553cb59158ac3642e2099"},
      {R"({"kind":"mesh","model_id":"PANEL"})", "23eef0ebeb1013a00817fd07659fea0e"},
  };
  auto bytes = [](const std::string& name) {
    std::ifstream in(testing::DataPath(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string panel = proto::ModelId(bytes("panel.obj"));
  ASSERT_TRUE(proto::IsSurfaceIdShaped(panel));
  json figure10 = json::parse(bytes("figure10.json"));
  figure10.erase("description");
  auto bezier =
      proto::ParseSurfaceRequest({{"surface", figure10}, {"sampling", {{"nu", 16}, {"nv", 16}}}});
  ASSERT_TRUE(bezier.ok()) << bezier.status().ToString();
  EXPECT_EQ(proto::SurfaceId(*bezier), "45ab9b0aa3b82492b465d26896b91e10");
  for (const auto& [surface, id] : cases) {
    std::string text = R"({"surface":)" + surface + R"(,"sampling":{"nu":16,"nv":16}})";
    if (const size_t at = text.find("PANEL"); at != std::string::npos) text.replace(at, 5, panel);
    auto request = proto::ParseSurfaceRequest(json::parse(text));
    ASSERT_TRUE(request.ok()) << request.status().ToString() << " " << text;
    EXPECT_EQ(proto::SurfaceId(*request), id) << text;
  }
}

}  // namespace
}  // namespace surfdeform
