// The API's JSON mapping: strict parsing, JSON paths in errors, canonical ids.
#include "proto/api.hpp"

#include <gtest/gtest.h>

#include "base/json_depth.hpp"
#include "json/bounded_json.hpp"
#include "proto/json_object.hpp"

namespace surfdeform::proto {
namespace {

using nlohmann::json;

Status ParseError(const std::string& text) {
  auto j = ParseBoundedJson(text, JsonLimits{}, "body");
  if (!j.ok()) return j.status();
  auto r = ParseSurfaceRequest(*j);
  return r.ok() ? Status::Ok() : r.status();
}

Status DeformError(const std::string& text) {
  auto j = ParseBoundedJson(text, JsonLimits{}, "params");
  if (!j.ok()) return j.status();
  auto r = ParseDeformParams(*j);
  return r.ok() ? Status::Ok() : r.status();
}

TEST(ApiJson, ParsesEveryKindAndKeepsDefaults) {
  const char* kinds[] = {
      R"({"surface":{"kind":"bezier","degree_u":1,"degree_v":1,
          "control_points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]]}})",
      R"({"surface":{"kind":"bspline","degree_u":1,"degree_v":1,"count_u":2,"count_v":2,
          "control_points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1]}})",
      R"({"surface":{"kind":"nurbs","degree_u":1,"degree_v":1,"count_u":2,"count_v":2,
          "control_points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],
          "weights":[1,2,1,1]}})",
      R"({"surface":{"kind":"cylinder","radius":2,"frame":{"origin":[1,2,3]}}})",
      R"({"surface":{"kind":"cone","radius_bottom":2,"radius_top":1}})",
      R"({"surface":{"kind":"sphere","radius":2}})",
      R"({"surface":{"kind":"torus","major_radius":3}})",
      R"({"surface":{"kind":"wave","time":0.5}})",
      R"({"surface":{"kind":"grid","nu":2,"nv":2,"points":[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}})"};
  for (const char* text : kinds) {
    auto r = ParseSurfaceRequest(json::parse(text));
    ASSERT_TRUE(r.ok()) << text << ": " << r.status().ToString();
    EXPECT_EQ(r->sampling.nu, 16);
    EXPECT_EQ(r->flatten.range, 3);
    // The canonical form parses back to the same id.
    auto again = ParseSurfaceRequest(CanonicalJson(*r));
    ASSERT_TRUE(again.ok()) << again.status().ToString();
    EXPECT_EQ(SurfaceId(*again), SurfaceId(*r)) << text;
  }
  auto c = ParseSurfaceRequest(json::parse(R"({"surface":{"kind":"cylinder","radius":2,
      "frame":{"origin":[1,2,3]}},"sampling":{"nu":8,"nv":9},"flatten":{"method":"paper","range":2}})"));
  ASSERT_TRUE(c.ok());
  const auto& cyl = std::get<CylinderSpec>(c->surface);
  EXPECT_EQ(cyl.radius, 2.0);
  EXPECT_EQ(cyl.height, 1.0);  // default kept
  EXPECT_EQ(cyl.frame.origin, Vec3(1, 2, 3));
  EXPECT_EQ(c->sampling.nv, 9);
  EXPECT_EQ(c->flatten.method, FlattenMethod::kPaper);
  EXPECT_EQ(c->flatten.range, 2);
}

TEST(ApiJson, UnknownFieldsAreErrorsWithPathAndSuggestion) {
  Status s = ParseError(R"({"surface":{"kind":"cylinder","radius":1,"heigth":2}})");
  EXPECT_EQ(s.code(), ErrorCode::kMalformed);
  EXPECT_EQ(s.field(), "surface.heigth");
  EXPECT_NE(s.message().find("did you mean \"height\""), std::string::npos) << s.message();

  s = ParseError(R"({"surface":{"kind":"cylinder"},"samplng":{"nu":4}})");
  EXPECT_EQ(s.field(), "samplng");
  s = ParseError(
      R"({"surface":{"kind":"cylinder"},"flatten":{"method":"majorization","rnage":3}})");
  EXPECT_EQ(s.field(), "flatten.rnage");
  s = ParseError(R"({"surface":{"kind":"cylinder","frame":{"orign":[0,0,0]}}})");
  EXPECT_EQ(s.field(), "surface.frame.orign");
  // A field of another kind is unknown for this one.
  s = ParseError(R"({"surface":{"kind":"cylinder","radius_top":1}})");
  EXPECT_EQ(s.field(), "surface.radius_top");
}

TEST(ApiJson, TypeErrorsNameTheJsonPath) {
  Status s = ParseError(R"({"surface":{"kind":"bezier","degree_u":1,"degree_v":1,
      "control_points":[[0,0,0],[1,0,0],[0,1,"x"],[1,1,1]]}})");
  EXPECT_EQ(s.code(), ErrorCode::kMalformed);
  EXPECT_EQ(s.field(), "surface.control_points[2][2]");
  s = ParseError(R"({"surface":{"kind":"cylinder","radius":"1"}})");
  EXPECT_EQ(s.field(), "surface.radius");
  EXPECT_NE(s.message().find("a string"), std::string::npos);
  s = ParseError(R"({"surface":{"kind":"spiral"}})");
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(s.field(), "surface.kind");
  s = ParseError(R"({"surface":{"radius":1}})");
  EXPECT_EQ(s.field(), "surface.kind");
  s = ParseError(R"([1,2])");
  EXPECT_EQ(s.code(), ErrorCode::kMalformed);
  s = ParseError(R"({"surface":{"kind":"cylinder"},"sampling":{"nu":4.5}})");
  EXPECT_EQ(s.field(), "sampling.nu");
}

TEST(ApiJson, OutOfRangeValuesAreInvalidArguments) {
  Status s = ParseError(R"({"surface":{"kind":"cylinder"},"sampling":{"nu":1}})");
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(s.field(), "sampling.nu");
  s = ParseError(R"({"surface":{"kind":"cylinder"},"flatten":{"range":0}})");
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(s.field(), "flatten.range");
  s = DeformError(R"({"surface":{"kind":"cylinder"},"placement":{"scale":-1}})");
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(s.field(), "placement.scale");
  s = DeformError(R"({"surface":{"kind":"cylinder"},"output":{"draco":{"speed":11}}})");
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(s.field(), "output.draco.speed");
}

TEST(ApiJson, SyntaxAndDepth) {
  Status s = ParseError(R"({"surface": )");
  EXPECT_EQ(s.code(), ErrorCode::kMalformed);
  EXPECT_NE(s.message().find("byte"), std::string::npos);
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  s = ParseError(deep);
  EXPECT_EQ(s.code(), ErrorCode::kMalformed);
  EXPECT_TRUE(s.has_limit());
  EXPECT_EQ(s.limit(), 32);
  EXPECT_EQ(s.actual(), 33);  // refused at the first level past the limit
  // Brackets inside strings do not count.
  EXPECT_EQ(surfdeform::JsonNestingDepth(R"({"a":"[[[[{{{{\"]]"})"), 1);
}

TEST(ApiJson, DeformParams) {
  auto r = ParseDeformParams(json::parse(R"({"surface_id":"0123456789abcdef0123456789abcdef",
      "placement":{"up":"-y","anchor":0.25,"center":{"fraction":[0.5,0.25]},"rotation_deg":30,
                   "scale":"fit","fit_margin":0.1,"outside":"clamp"},
      "subdivision":{"mode":"off"},
      "output":{"format":"glb","draco":{"position_bits":16,"sequential":true}}})"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_FALSE(r->surface.has_value());
  EXPECT_EQ(r->placement.up, UpAxis::kNegY);
  EXPECT_EQ(r->placement.anchor, AnchorMode::kValue);
  EXPECT_EQ(r->placement.anchor_value, 0.25);
  EXPECT_EQ(r->placement.center_mode, CenterMode::kFraction);
  EXPECT_EQ(r->placement.center, Vec2(0.5, 0.25));
  EXPECT_TRUE(r->placement.fit);
  EXPECT_EQ(r->placement.outside, OutsideMode::kClamp);
  EXPECT_EQ(r->output.format, OutputFormat::kGlb);
  EXPECT_EQ(r->output.draco.position_bits, 16);
  EXPECT_TRUE(r->output.draco.sequential);

  // Exactly one of surface and surface_id.
  EXPECT_EQ(DeformError(R"({"placement":{}})").field(), "surface");
  EXPECT_EQ(DeformError(R"({"surface":{"kind":"cylinder"},"surface_id":"x"})").field(),
            "surface_id");
  EXPECT_EQ(DeformError(R"({"surface_id":"not-an-id"})").code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(DeformError(R"({"surface":{"kind":"cylinder"},"subdivision":{"mode":"fine"}})").field(),
            "subdivision.mode");
  EXPECT_EQ(
      DeformError(R"({"surface":{"kind":"cylinder"},"subdivision":{"tolerance":-1}})").field(),
      "subdivision.tolerance");
  EXPECT_EQ(DeformError(R"({"surface":{"kind":"cylinder"},"subdivision":{"epsilon":"x"}})").field(),
            "subdivision.epsilon");
  EXPECT_EQ(DeformError(R"({"surface":{"kind":"cylinder"},"subdivision":{"tolerence":1}})").field(),
            "subdivision.tolerence");
}

TEST(ApiJson, SubdivisionDefaultsToAdaptiveAndReadsItsOptions) {
  auto d = ParseDeformParams(json::parse(R"({"surface":{"kind":"cylinder"}})"));
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->subdivision.mode, SubdivisionMode::kAdaptive);
  EXPECT_EQ(d->subdivision.tolerance, 0.0);
  auto r = ParseDeformParams(json::parse(
      R"({"surface":{"kind":"cylinder"},
          "subdivision":{"mode":"uniform","epsilon":0.5,"tolerance":0.002}})"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->subdivision.mode, SubdivisionMode::kUniform);
  EXPECT_EQ(r->subdivision.epsilon, 0.5);
  EXPECT_EQ(r->subdivision.tolerance, 0.002);
  EXPECT_EQ(
      DeformError(R"({"surface":{"kind":"cylinder"},"placement":{"center":"middle"}})").field(),
      "placement.center");
}

TEST(ApiJson, IdsAreContentHashes) {
  auto a = ParseSurfaceRequest(json::parse(R"({"surface":{"kind":"cylinder","radius":1}})"));
  // Same content spelled differently: key order, explicit defaults, 1 vs 1.0.
  auto b = ParseSurfaceRequest(json::parse(
      R"({"sampling":{"nv":16},"surface":{"radius":1.0,"height":1,"kind":"cylinder"}})"));
  auto c =
      ParseSurfaceRequest(json::parse(R"({"surface":{"kind":"cylinder","radius":1.0000001}})"));
  auto d = ParseSurfaceRequest(
      json::parse(R"({"surface":{"kind":"cylinder","radius":1},"sampling":{"nu":17}})"));
  ASSERT_TRUE(a.ok() && b.ok() && c.ok() && d.ok());
  EXPECT_EQ(SurfaceId(*a), SurfaceId(*b));
  EXPECT_NE(SurfaceId(*a), SurfaceId(*c));
  EXPECT_NE(SurfaceId(*a), SurfaceId(*d));
  EXPECT_TRUE(IsSurfaceIdShaped(SurfaceId(*a)));
  EXPECT_FALSE(IsSurfaceIdShaped("../../etc/passwd"));
}

TEST(ApiJson, PeriodicUIsPartOfTheIdOnlyWhenSet) {
  const std::string grid =
      R"("kind":"grid","nu":4,"nv":2,"points":[[1,0,0],[0,1,0],[-1,0,0],[1,0,0],)"
      R"([1,0,1],[0,1,1],[-1,0,1],[1,0,1]])";
  auto plain = ParseSurfaceRequest(json::parse("{\"surface\":{" + grid + "}}"));
  auto unset =
      ParseSurfaceRequest(json::parse("{\"surface\":{" + grid + ",\"periodic_u\":false}}"));
  auto closed =
      ParseSurfaceRequest(json::parse("{\"surface\":{" + grid + ",\"periodic_u\":true}}"));
  ASSERT_TRUE(plain.ok() && unset.ok() && closed.ok());
  EXPECT_TRUE(std::get<GridSpec>(closed->surface).periodic_u);
  EXPECT_EQ(SurfaceId(*plain), SurfaceId(*unset));  // ids of earlier requests stay
  EXPECT_NE(SurfaceId(*plain), SurfaceId(*closed));
  EXPECT_FALSE(CanonicalJson(*plain)["surface"].contains("periodic_u"));
  EXPECT_EQ(CanonicalJson(*closed)["surface"]["periodic_u"], true);
  EXPECT_EQ(ParseError(R"({"surface":{"kind":"cylinder","periodic_u":true}})").code(),
            ErrorCode::kMalformed);  // analytic kinds close by their angles
}

// A key given twice in one object is refused, wherever it is; the same key
// in two objects is not a duplicate.
TEST(ApiJson, DuplicateKeysAreRefusedWithTheirPath) {
  auto j = ParseBoundedJson(R"({"surface":{"kind":"cone","radius_top":1,"radius_top":2}})",
                            JsonLimits{}, "params");
  ASSERT_FALSE(j.ok());
  EXPECT_EQ(j.status().code(), ErrorCode::kMalformed);
  EXPECT_EQ(j.status().field(), "params.surface.radius_top");
  j = ParseBoundedJson(R"({"a":1,"b":{"a":1},"c":[{"a":1},{"a":2}],"d":2})", JsonLimits{},
                       "params");
  EXPECT_TRUE(j.ok()) << j.status().ToString();
  j = ParseBoundedJson(R"({"a":1,"b":{"x":1},"a":2})", JsonLimits{}, "params");
  ASSERT_FALSE(j.ok());
  EXPECT_EQ(j.status().field(), "params.a");
}

// Every value of `given` at its path in `written`: a field that the writer
// drops or changes fails here.
void ExpectHolds(const json& written, const json& given, const std::string& path) {
  if (given.is_object()) {
    ASSERT_TRUE(written.is_object()) << path << ": " << written.dump();
    for (const auto& [key, value] : given.items()) {
      ASSERT_TRUE(written.contains(key)) << path << "." << key << " was not written";
      ExpectHolds(written.at(key), value, path + "." + key);
    }
  } else if (given.is_array()) {
    ASSERT_TRUE(written.is_array() && written.size() == given.size())
        << path << ": " << written.dump();
    for (size_t i = 0; i < given.size(); ++i) {
      ExpectHolds(written.at(i), given.at(i), path + "[" + std::to_string(i) + "]");
    }
  } else if (given.is_number()) {
    EXPECT_EQ(written.get<double>(), given.get<double>()) << path;
  } else {
    EXPECT_EQ(written, given) << path;
  }
}

// `given`, read by `parse` and written by ToJson, holds every given value
// and reads back into a request that writes the same.
template <typename Parse>
void ExpectReadsBack(const json& given, Parse parse) {
  SCOPED_TRACE(given.dump());
  auto request = parse(given);
  ASSERT_TRUE(request.ok()) << request.status().ToString();
  const json written = ToJson(*request);
  ExpectHolds(written, given, "");
  auto again = parse(written);
  ASSERT_TRUE(again.ok()) << again.status().ToString() << " in " << written.dump();
  EXPECT_EQ(ToJson(*again), written);
}

// Requests with every field away from its default: written by ToJson, they
// hold every given value and read back into requests that write the same.
TEST(ApiJson, WrittenRequestsReadBackTheSame) {
  const std::string mesh_parts = R"("model_id":"00112233445566778899aabbccddeeff",
      "placement":{"up":"-y","rigid":"components","anchor":0.25,"center":{"fraction":[0.5,0.25]},
                   "rotation_deg":30,"scale":"fit","fit_margin":0.1,"outside":"clamp"},
      "subdivision":{"mode":"uniform","epsilon":0.5,"tolerance":0.002})";
  const std::string flatten = R"("sampling":{"nu":9,"nv":7},
      "flatten":{"method":"paper","range":2,"tolerance":1e-5,"max_iterations":50,"step":0.01,
                 "exact_developable":false,"lattice_factor":3,"relax_steps":1})";
  const std::string deforms[] = {
      R"({"surface":{"kind":"cylinder","radius":2,"angle_deg":90,"height":3},
          "warm_start":"fedcba9876543210fedcba9876543210",)" +
          flatten + "," + mesh_parts +
          R"(,"output":{"format":"glb","draco":{"position_bits":16,"normal_bits":8,
             "uv_bits":10,"color_bits":6,"speed":3,"sequential":true},"distortion":true}})",
      R"({"surface_id":"0123456789abcdef0123456789abcdef",)" + mesh_parts +
          R"(,"placement":{"up":"+x","anchor":"top","center":[1.5,-2],"scale":3,
             "outside":"extrapolate"},"output":{"compression":"meshopt"}})",
      R"({"animation":{"keyframes":[{"time":0,"surface":{"kind":"wave","amplitude":0.1}},
          {"time":1,"surface":{"kind":"wave","amplitude":0.3}}],"interpolation":"linear",
          "frames":5,"fps":10},"frame":3,)" +
          flatten + "," + mesh_parts + R"(,"output":{"format":"ply"}})",
  };
  for (const std::string& text : deforms) ExpectReadsBack(json::parse(text), ParseDeformParams);

  const json animate = json::parse(
      R"({"animation":{"keyframes":[{"time":0,"surface":{"kind":"wave","amplitude":0.1}},
          {"time":2,"surface":{"kind":"wave","amplitude":0.3}}],"frames":4,"fps":12},)" +
      flatten + "," + mesh_parts + R"(,"output":{"compression":"none"}})");
  ExpectReadsBack(animate, ParseAnimateParams);

  const json create = json::parse(
      R"({"warm_start":"0123456789abcdef0123456789abcdef",
          "surface":{"kind":"mesh","model_id":"00112233445566778899aabbccddeeff"},)" +
      flatten + "}");
  ExpectReadsBack(create, ParseCreateSurfaceRequest);
  auto c = ParseCreateSurfaceRequest(create);
  auto c_again = ParseCreateSurfaceRequest(ToJson(*c));
  ASSERT_TRUE(c.ok() && c_again.ok());
  EXPECT_EQ(SurfaceId(c_again->request), SurfaceId(c->request));
}

}  // namespace
}  // namespace surfdeform::proto
