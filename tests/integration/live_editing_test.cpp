// What a live editor (the viewer) stands on, on the real server. Models
// uploaded once (POST /v1/models) and used by id: 201 then 200 for the same
// bytes, the summary, deformations and animations by "model_id"
// byte-identical to sending the mesh, and the errors (404 unknown_model, a
// mesh and an id at once, an id the bytes do not have). The field of the
// sheet-to-surface map (GET /v1/surfaces/{id}/field): JSON and bytes that
// agree, cacheable forever, its limits, and with POST /v1/surfaces in one
// round trip.
#include <gtest/gtest.h>
#include <httplib.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "proto/content_hash.hpp"
#include "server_process.hpp"
#include "shared_server.hpp"

namespace surfdeform::testing {
namespace {

using nlohmann::json;

const char kSurface[] =
    R"("surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},"sampling":{"nu":16,"nv":16})";
const char kUnknown[] = "0123456789abcdef0123456789abcdef";

// A deformation's statistics without what depends on the caches' state.
json Uncached(const std::string& stats) {
  json j = json::parse(stats);
  j.erase("cached");
  j["placement"].erase("reused");
  j["subdivision"].erase("reused");
  return j;
}

class LiveEditingTest : public SharedServerTest<LiveEditingTest> {
 public:
  // Every answer made, none kept: these tests compare the work done by id
  // and inline (answers_test.cpp tests the kept ones).
  static std::vector<std::string> Args() {
    return {"--log-level", "warn", "--answer-cache-mib", "0"};
  }

 protected:
  static httplib::Client Client() {
    httplib::Client c("127.0.0.1", port());
    c.set_read_timeout(60, 0);
    return c;
  }
  static std::string Bunny() {
    auto r = Client().Get("/samples/bunny.ply");
    EXPECT_TRUE(r && r->status == 200) << "the viewer's samples are served";
    return r ? r->body : std::string();
  }
  // The problem+json of a failed request: its status and "code".
  static json Problem(const httplib::Result& r, int status, const std::string& code) {
    EXPECT_TRUE(r) << "no response";
    if (!r) return json::object();
    EXPECT_EQ(r->status, status) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    json j = json::parse(r->body, nullptr, false);
    EXPECT_EQ(j.value("code", ""), code) << r->body;
    return j;
  }
};

TEST_F(LiveEditingTest, TheFirstUploadCreatesTheSameBytesAgainFindIt) {
  auto c = Client();
  const std::string bunny = Bunny();
  const std::string id = proto::Sha256Hex(bunny, 32);
  auto first = c.Post("/v1/models", bunny, "application/octet-stream");
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 201) << first->body;
  EXPECT_EQ(first->get_header_value("Location"), "/v1/models/" + id);
  const json summary = json::parse(first->body);
  EXPECT_EQ(summary.at("id"), id);
  EXPECT_EQ(summary.at("format"), "ply");
  EXPECT_EQ(summary.at("file_bytes"), bunny.size());
  EXPECT_EQ(summary.at("vertices"), 37706);  // the viewer's sample's header says so
  EXPECT_EQ(summary.at("triangles"), 75408);
  EXPECT_EQ(summary.at("up"), "+z");
  const json& bounds = summary.at("bounds");
  for (int k = 0; k < 3; ++k) EXPECT_LT(bounds[0][k].get<double>(), bounds[1][k].get<double>());

  // The same bytes again, raw or as a form's part, and on the id header.
  httplib::Headers routed = {{"X-Surfdeform-Model-Id", id}};
  auto again = c.Post("/v1/models", routed, bunny, "application/octet-stream");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200);
  EXPECT_EQ(again->body, first->body);
  auto form = c.Post("/v1/models", httplib::MultipartFormDataItems{
                                       {"mesh", bunny, "bunny.ply", "application/octet-stream"}});
  ASSERT_TRUE(form);
  EXPECT_EQ(form->status, 200);
  EXPECT_EQ(form->body, first->body);

  auto got = c.Get("/v1/models/" + id);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->status, 200);
  EXPECT_EQ(got->body, first->body);
  EXPECT_EQ(got->get_header_value("ETag"), first->get_header_value("ETag"));
}

TEST_F(LiveEditingTest, ADeformationByIdIsByteIdenticalToSendingTheMesh) {
  auto c = Client();
  const std::string bunny = Bunny();
  auto up = c.Post("/v1/models", bunny, "application/octet-stream");
  ASSERT_TRUE(up && (up->status == 201 || up->status == 200));
  const std::string id = json::parse(up->body).at("id");
  for (const char* format : {"drc", "glb", "ply"}) {
    const std::string options =
        std::string(R"("placement":{"scale":0.6},"output":{"format":")") + format + "\"}";
    const std::string with_mesh = std::string("{") + kSurface + "," + options + "}";
    const std::string by_id =
        std::string(R"({"model_id":")") + id + "\"," + kSurface + "," + options + "}";
    auto sent = c.Post("/v1/deform", httplib::MultipartFormDataItems{
                                         {"mesh", bunny, "bunny.ply", "application/octet-stream"},
                                         {"params", with_mesh, "", "application/json"}});
    ASSERT_TRUE(sent);
    ASSERT_EQ(sent->status, 200) << sent->body;
    // By id, as a JSON body and as a form with no mesh part.
    auto json_body = c.Post("/v1/deform", by_id, "application/json");
    ASSERT_TRUE(json_body);
    ASSERT_EQ(json_body->status, 200) << json_body->body;
    EXPECT_TRUE(json_body->body == sent->body) << format;
    EXPECT_EQ(json_body->get_header_value("ETag"), sent->get_header_value("ETag"));
    // The statistics too, but for what the second request found cached.
    EXPECT_EQ(Uncached(json_body->get_header_value("X-Surfdeform-Stats")),
              Uncached(sent->get_header_value("X-Surfdeform-Stats")));
    auto form = c.Post("/v1/deform",
                       httplib::MultipartFormDataItems{{"params", by_id, "", "application/json"}});
    ASSERT_TRUE(form);
    ASSERT_EQ(form->status, 200) << form->body;
    EXPECT_TRUE(form->body == sent->body) << format;
  }
}

TEST_F(LiveEditingTest, AnAnimationByIdIsByteIdenticalToSendingTheMesh) {
  auto c = Client();
  const std::string plate = "v -1 -0.5 0\nv 1 -0.5 0\nv 1 0.5 0\nv -1 0.5 0\nf 1 2 3 4\n";
  auto up = c.Post("/v1/models", plate, "application/octet-stream");
  ASSERT_TRUE(up && up->status == 201) << (up ? up->body : "");
  const std::string animation =
      R"("animation":{"frames":4,"fps":8,"keyframes":[
        {"time":0,"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":90}},
        {"time":1,"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180}}]},
        "sampling":{"nu":8,"nv":8})";
  auto sent = c.Post("/v1/animate", httplib::MultipartFormDataItems{
                                        {"mesh", plate, "plate.obj", "application/octet-stream"},
                                        {"params", "{" + animation + "}", "", "application/json"}});
  ASSERT_TRUE(sent);
  ASSERT_EQ(sent->status, 200) << sent->body;
  const std::string id = proto::Sha256Hex(plate, 32);
  auto by_id =
      c.Post("/v1/animate", R"({"model_id":")" + id + "\"," + animation + "}", "application/json");
  ASSERT_TRUE(by_id);
  ASSERT_EQ(by_id->status, 200) << by_id->body;
  EXPECT_TRUE(by_id->body == sent->body);
}

TEST_F(LiveEditingTest, UnknownIdsAndConflictingRequestsAreClearErrors) {
  auto c = Client();
  // Never uploaded: 404 unknown_model, on every route that takes an id.
  json p = Problem(
      c.Post("/v1/deform", std::string(R"({"model_id":")") + kUnknown + "\"," + kSurface + "}",
             "application/json"),
      404, "unknown_model");
  EXPECT_EQ(p.value("field", ""), "model_id");
  EXPECT_NE(p.value("detail", "").find("/v1/models"), std::string::npos) << p.dump();
  p = Problem(c.Get(std::string("/v1/models/") + kUnknown), 404, "unknown_model");
  EXPECT_EQ(p.value("field", ""), "id");
  auto traversal = c.Get("/v1/models/..%2F..%2Fetc%2Fpasswd");
  ASSERT_TRUE(traversal);
  EXPECT_EQ(traversal->status, 404);
  // A model_id that is not an id's shape.
  p = Problem(c.Post("/v1/deform", std::string(R"({"model_id":"bunny",)") + kSurface + "}",
                     "application/json"),
              422, "invalid_argument");
  EXPECT_EQ(p.value("field", ""), "model_id");

  const std::string plate = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  ASSERT_TRUE(c.Post("/v1/models", plate, "application/octet-stream"));
  const std::string id = proto::Sha256Hex(plate, 32);
  // A mesh and an id at once.
  p = Problem(c.Post("/v1/deform",
                     httplib::MultipartFormDataItems{
                         {"mesh", plate, "p.obj", "application/octet-stream"},
                         {"params", R"({"model_id":")" + id + "\"," + kSurface + "}", "",
                          "application/json"}}),
              400, "malformed");
  EXPECT_EQ(p.value("field", ""), "model_id");
  // Neither: the error says how to name one.
  p = Problem(c.Post("/v1/deform", std::string("{") + kSurface + "}", "application/json"), 400,
              "malformed");
  EXPECT_EQ(p.value("field", ""), "mesh");
  EXPECT_NE(p.value("detail", "").find("model_id"), std::string::npos);
  // The parameters twice: a JSON body and the header.
  Problem(c.Post("/v1/deform", {{"X-Surfdeform-Params", "{}"}},
                 R"({"model_id":")" + id + "\"," + kSurface + "}", "application/json"),
          400, "malformed");

  // Uploads: no bytes, bytes in no format, a wrong id header, a form with more.
  Problem(c.Post("/v1/models", "", "application/octet-stream"), 400, "malformed");
  Problem(c.Post("/v1/models", "\x89PNG\r\n\x1a\n not a mesh", "application/octet-stream"), 415,
          "unsupported_format");
  p = Problem(c.Post("/v1/models", {{"X-Surfdeform-Model-Id", kUnknown}}, plate,
                     "application/octet-stream"),
              400, "malformed");
  EXPECT_EQ(p.value("field", ""), "X-Surfdeform-Model-Id");
  Problem(
      c.Post("/v1/models",
             httplib::MultipartFormDataItems{{"mesh", plate, "p.obj", "application/octet-stream"},
                                             {"params", "{}", "", "application/json"}}),
      400, "malformed");
}

TEST_F(LiveEditingTest, TheBudgetIsPublishedAndTheCacheCounted) {
  auto c = Client();
  auto info = c.Get("/v1/info");
  ASSERT_TRUE(info && info->status == 200);
  EXPECT_EQ(json::parse(info->body).at("limits").at("model_cache_bytes"), 256u << 20);
  const std::string square = "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4\n";
  const double before = ScrapeMetric(port(), "surfdeform_model_cache_misses_total");
  ASSERT_TRUE(c.Post("/v1/models", square, "application/octet-stream"));
  ASSERT_TRUE(c.Post("/v1/models", square, "application/octet-stream"));
  EXPECT_EQ(ScrapeMetric(port(), "surfdeform_model_cache_misses_total"), before + 1);
  EXPECT_GE(ScrapeMetric(port(), "surfdeform_model_cache_entries"), 1);
}

std::string CreateSurface(httplib::Client& c, const std::string& query = "",
                          json* reply = nullptr) {
  auto r = c.Post("/v1/surfaces" + query, std::string("{") + kSurface + "}", "application/json");
  EXPECT_TRUE(r && (r->status == 200 || r->status == 201)) << (r ? r->body : "no reply");
  if (!r) return "";
  const json j = json::parse(r->body);
  if (reply != nullptr) *reply = j;
  return j.at("id");
}

TEST_F(LiveEditingTest, TheFieldsJsonAndBytesAgreeAndAreCachedForever) {
  auto c = Client();
  const std::string id = CreateSurface(c);
  auto text = c.Get("/v1/surfaces/" + id + "/field?n=9");
  ASSERT_TRUE(text);
  ASSERT_EQ(text->status, 200) << text->body;
  EXPECT_EQ(text->get_header_value("Content-Type"), "application/json");
  EXPECT_EQ(text->get_header_value("Cache-Control"), "public, max-age=31536000, immutable");
  EXPECT_EQ(text->get_header_value("Vary"), "Accept");
  const json j = json::parse(text->body);
  ASSERT_EQ(j.at("n"), 9);
  ASSERT_EQ(j.at("positions").size(), 81u);
  ASSERT_EQ(j.at("normals").size(), 81u);
  ASSERT_EQ(j.at("on_sheet").size(), 81u);

  auto bytes = c.Get("/v1/surfaces/" + id + "/field?n=9", {{"Accept", "application/octet-stream"}});
  ASSERT_TRUE(bytes);
  ASSERT_EQ(bytes->status, 200);
  EXPECT_EQ(bytes->get_header_value("Content-Type"), "application/octet-stream");
  EXPECT_NE(bytes->get_header_value("ETag"), text->get_header_value("ETag"));
  const std::string& b = bytes->body;
  ASSERT_EQ(j.at("params").size(), 81u);
  ASSERT_EQ(b.size(), 32u + 81u * 24u + 81u + 81u * 8u);  // the documented layout
  EXPECT_EQ(b.substr(0, 4), "SDFD");
  auto u32 = [&b](size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
  };
  auto f32 = [&b](size_t at) {
    float v;
    std::memcpy(&v, b.data() + at, 4);
    return static_cast<double>(v);
  };
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), 9u);
  const json& bounds = j.at("bounds");
  EXPECT_EQ(f32(16), static_cast<float>(bounds[0][0].get<double>()));
  EXPECT_EQ(f32(28), static_cast<float>(bounds[1][1].get<double>()));
  int on = 0;
  for (size_t k = 0; k < 81; ++k) {
    for (size_t c3 = 0; c3 < 3; ++c3) {
      EXPECT_EQ(f32(32 + 12 * k + 4 * c3), static_cast<float>(j["positions"][k][c3].get<double>()));
      EXPECT_EQ(f32(32 + 81 * 12 + 12 * k + 4 * c3),
                static_cast<float>(j["normals"][k][c3].get<double>()));
    }
    EXPECT_EQ(b[32 + 81 * 24 + k] == 1, j["on_sheet"][k].get<bool>());
    for (size_t c2 = 0; c2 < 2; ++c2) {
      EXPECT_EQ(f32(32 + 81 * 25 + 8 * k + 4 * c2),
                static_cast<float>(j["params"][k][c2].get<double>()));
    }
    on += j["on_sheet"][k].get<bool>();
  }
  EXPECT_EQ(on, 81);  // an unrolled cylinder is its bounding box

  // Never brotli (httplib's takes 0.7 s for 0.5 MB): gzip where offered.
  auto packed = c.Get("/v1/surfaces/" + id + "/field?n=64", {{"Accept-Encoding", "br, gzip"}});
  ASSERT_TRUE(packed);
  EXPECT_EQ(packed->status, 200);
  EXPECT_EQ(packed->get_header_value("Content-Encoding"), "gzip");
  EXPECT_EQ(packed->get_header_value("Vary"), "Accept");  // and Accept-Encoding
  EXPECT_EQ(json::parse(packed->body).at("n"), 64);       // inflated once: JSON
  // At zlib's fastest level (the gzip header's XFL byte is 4), not httplib's
  // default (0): 3.5 against 22 ms for a live edit's 0.4 MB field.
  auto raw_client = Client();
  raw_client.set_decompress(false);
  auto raw = raw_client.Get("/v1/surfaces/" + id + "/field?n=64", {{"Accept-Encoding", "gzip"}});
  ASSERT_TRUE(raw);
  ASSERT_GT(raw->body.size(), 10u);
  EXPECT_EQ(static_cast<unsigned char>(raw->body[0]), 0x1f);
  EXPECT_EQ(static_cast<unsigned char>(raw->body[1]), 0x8b);
  EXPECT_EQ(static_cast<int>(raw->body[8]), 4);
  auto only_br = c.Get("/v1/surfaces/" + id + "/field?n=64", {{"Accept-Encoding", "br"}});
  ASSERT_TRUE(only_br);
  EXPECT_EQ(only_br->get_header_value("Content-Encoding"), "");

  // The same request again: 304 for the tag the client holds.
  auto again = c.Get("/v1/surfaces/" + id + "/field?n=9",
                     {{"If-None-Match", text->get_header_value("ETag")}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
}

TEST_F(LiveEditingTest, AnEditIsOneRoundTripAndTheFieldsLimitsAreClear) {
  auto c = Client();
  json created;
  const std::string id = CreateSurface(c, "?field=16", &created);
  ASSERT_TRUE(created.contains("field")) << created.dump().substr(0, 300);
  auto alone = c.Get("/v1/surfaces/" + id + "/field?n=16");
  ASSERT_TRUE(alone && alone->status == 200);
  EXPECT_EQ(created["field"], json::parse(alone->body));
  json plain;
  CreateSurface(c, "", &plain);
  EXPECT_FALSE(plain.contains("field"));

  auto info = c.Get("/v1/info");
  ASSERT_TRUE(info);
  const int side = json::parse(info->body).at("limits").at("max_field_side");
  EXPECT_GE(side, 512);
  json p = Problem(c.Get("/v1/surfaces/" + id + "/field?n=" + std::to_string(side + 1)), 413,
                   "limit_exceeded");
  EXPECT_EQ(p.value("field", ""), "n");
  EXPECT_EQ(p.value("limit", 0), side);
  EXPECT_EQ(p.value("actual", 0), side + 1);
  p = Problem(c.Get("/v1/surfaces/" + id + "/field?n=1"), 422, "invalid_argument");
  EXPECT_EQ(p.value("field", ""), "n");
  p = Problem(c.Get("/v1/surfaces/" + id + "/field?n=-3"), 400, "malformed");
  EXPECT_EQ(p.value("field", ""), "n");
  p = Problem(
      c.Post("/v1/surfaces?field=99999", std::string("{") + kSurface + "}", "application/json"),
      413, "limit_exceeded");
  EXPECT_EQ(p.value("field", ""), "field");
  Problem(c.Get(std::string("/v1/surfaces/") + kUnknown + "/field"), 404, "not_found");
}

TEST_F(LiveEditingTest, AnEditStartsWarmFromTheSurfaceItNamesOrSaysWhyNot) {
  auto c = Client();
  const std::string bezier =
      R"("surface":{"kind":"bezier","degree_u":2,"degree_v":2,"control_points":[[0,0,0],[1,0,0.3],[2,0,0],[0,1,0.2],[1,1,LIFT],[2,1,0.2],[0,2,0],[1,2,0.3],[2,2,0]]},"sampling":{"nu":12,"nv":12})";
  auto with = [&](const std::string& lift, const std::string& extra) {
    std::string s = bezier;
    s.replace(s.find("LIFT"), 4, lift);
    return "{" + s + extra + "}";
  };
  auto post = [&](const std::string& body, int status) {
    auto r = c.Post("/v1/surfaces", body, "application/json");
    EXPECT_TRUE(r && r->status == status) << (r ? r->body : "no reply");
    return r ? json::parse(r->body, nullptr, false) : json();
  };
  const double paths_hits = ScrapeMetric(port(), "surfdeform_edit_paths_hits_total");
  const json first = post(with("0.5", ""), 201);
  EXPECT_FALSE(first.contains("warm_start"));
  const std::string id = first.at("id");
  const json edit = post(with("0.52", R"(,"warm_start":")" + id + "\""), 201);
  const json& w = edit.at("warm_start");
  EXPECT_EQ(w.at("from"), id);
  EXPECT_EQ(w.at("used"), true) << w.dump();
  EXPECT_LT(w.at("iterations").get<int>(), first.at("quality").at("iterations").get<int>());
  EXPECT_GT(w.at("iterations_saved_estimate").get<int>(), 0);
  // The first surface was made by POST /v1/surfaces, so its distance paths
  // were kept: the edit measured from them (a 12 x 12 bent patch: most of
  // its ~1,700 pairs follow a path).
  EXPECT_GT(w.at("paths_reused").get<int>(), 500) << w.dump();
  EXPECT_EQ(ScrapeMetric(port(), "surfdeform_edit_paths_hits_total"), paths_hits + 1);
  EXPECT_GE(ScrapeMetric(port(), "surfdeform_edit_paths_entries"), 2);
  // How the new sheet lies against the one it started from: a small turn
  // and shift of the canonical frame, and a small rest.
  const json& motion = w.at("motion");
  EXPECT_LT(std::abs(motion.at("rotation_deg").get<double>()), 5.0) << motion.dump();
  EXPECT_EQ(motion.at("translation").size(), 2u);
  EXPECT_LT(motion.at("rms").get<double>(), 0.05) << motion.dump();
  // The first edit started from a cold sheet; the next starts ahead along
  // it, as far as it repeats it (0.015 of its 0.02 lift), and one that goes
  // back starts behind.
  EXPECT_FALSE(w.contains("extrapolated")) << w.dump();
  const json on =
      post(with("0.535", R"(,"warm_start":")" + edit.at("id").get<std::string>() + "\""), 201);
  EXPECT_NEAR(on.at("warm_start").at("extrapolated").get<double>(), 0.75, 1e-9) << on.dump();
  const json back =
      post(with("0.525", R"(,"warm_start":")" + on.at("id").get<std::string>() + "\""), 201);
  EXPECT_NEAR(back.at("warm_start").at("extrapolated").get<double>(), -2.0 / 3.0, 1e-9)
      << back.dump();
  // Not an error when it cannot be used: a cold start, and why.
  const json unknown = post(with("0.54", R"(,"warm_start":")" + std::string(kUnknown) + "\""), 201);
  EXPECT_EQ(unknown.at("warm_start").at("used"), false);
  EXPECT_NE(unknown.at("warm_start").at("reason").get<std::string>().find("unknown"),
            std::string::npos);
  std::string other_grid = with("0.56", R"(,"warm_start":")" + id + "\"");
  other_grid.replace(other_grid.find("\"nu\":12"), 7, "\"nu\":14");
  const json grid = post(other_grid, 201);
  EXPECT_EQ(grid.at("warm_start").at("used"), false);
  EXPECT_NE(grid.at("warm_start").at("reason").get<std::string>().find("grid"), std::string::npos);
  const json cached = post(with("0.52", R"(,"warm_start":")" + id + "\""), 200);
  EXPECT_EQ(cached.at("warm_start").at("used"), false);
  EXPECT_TRUE(cached.at("warm_start").contains("motion"));  // found: said either way
  EXPECT_EQ(cached.at("id"), edit.at("id"));                // the id names the surface alone
  json p =
      Problem(c.Post("/v1/surfaces", with("0.5", R"(,"warm_start":"nope")"), "application/json"),
              422, "invalid_argument");
  EXPECT_EQ(p.value("field", ""), "warm_start");
}

// The mean of an OBJ's vertices.
std::array<double, 3> ObjCentroid(const std::string& obj) {
  std::istringstream in(obj);
  std::string line;
  std::array<double, 3> sum{0, 0, 0};
  int n = 0;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream v(line.substr(2));
    double x = 0, y = 0, z = 0;
    v >> x >> y >> z;
    sum[0] += x, sum[1] += y, sum[2] += z;
    ++n;
  }
  for (double& c : sum) c /= std::max(n, 1);
  return sum;
}

double Distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

TEST_F(LiveEditingTest, AnEditsDeformationMovesThePlacementWithTheSheetInOneRoundTrip) {
  auto c = Client();
  // A 0.3-wide square tile, 0.05 thick, uploaded once.
  const std::string tile =
      "v -0.15 -0.15 0\nv 0.15 -0.15 0\nv 0.15 0.15 0\nv -0.15 0.15 0\n"
      "v -0.15 -0.15 0.05\nv 0.15 -0.15 0.05\nv 0.15 0.15 0.05\nv -0.15 0.15 0.05\n"
      "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n";
  auto up = c.Post("/v1/models", tile, "application/octet-stream");
  ASSERT_TRUE(up && (up->status == 201 || up->status == 200)) << (up ? up->body : "no reply");
  const std::string model = json::parse(up->body).at("id");
  // A bent patch, then an edit of its corner control point: the canonical
  // frame (sample (0, 0) at the origin) turns and shifts under the model.
  auto patch = [](const std::string& corner) {
    return R"("surface":{"kind":"bezier","degree_u":2,"degree_v":2,"control_points":[)" + corner +
           R"(,[1,0,0.3],[2,0,0],[0,1,0.2],[1,1,0.5],[2,1,0.2],[0,2,0],[1,2,0.3],[2,2,0]]},"sampling":{"nu":12,"nv":12})";
  };
  const std::string before = patch("[0,0,0]"), after = patch("[0,-0.1,0.35]");
  auto created = c.Post("/v1/surfaces", "{" + before + "}", "application/json");
  ASSERT_TRUE(created && created->status / 100 == 2) << (created ? created->body : "no reply");
  const std::string from = json::parse(created->body).at("id");
  auto deform = [&](const std::string& where, const std::string& placement) {
    auto r = c.Post("/v1/deform",
                    R"({"model_id":")" + model + "\"," + where + R"(,"placement":)" + placement +
                        R"(,"subdivision":{"mode":"off"},"output":{"format":"obj"}})",
                    "application/json");
    EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "no reply");
    return r;
  };
  const std::string asked = R"({"center":[1.3,0.8],"rotation_deg":20,"scale":1})";
  auto on_before = deform(R"("surface_id":")" + from + "\"", asked);
  // The edit and its deformation in one request, the placement given on the
  // sheet it started from.
  auto edit = deform(after + R"(,"warm_start":")" + from + "\"", asked);
  ASSERT_TRUE(on_before && edit);
  const json stats = json::parse(edit->get_header_value("X-Surfdeform-Stats"));
  const json& w = stats.at("warm_start");
  EXPECT_EQ(w.at("from"), from);
  EXPECT_EQ(w.at("used"), true) << w.dump();
  // Moved by the motion POST /v1/surfaces reports for the same edit.
  auto same =
      c.Post("/v1/surfaces", "{" + after + R"(,"warm_start":")" + from + "\"}", "application/json");
  ASSERT_TRUE(same && same->status == 200) << (same ? same->body : "no reply");
  const json summary = json::parse(same->body);
  EXPECT_EQ(summary.at("id"), stats.at("surface_id"));  // flattened by the deformation
  const json& m = summary.at("warm_start").at("motion");
  const double turn = m.at("rotation_deg").get<double>() * M_PI / 180.0;
  EXPECT_GT(std::abs(m.at("rotation_deg").get<double>()), 1.0) << "the edit turns the frame";
  const double cx =
      std::cos(turn) * 1.3 - std::sin(turn) * 0.8 + m.at("translation")[0].get<double>();
  const double cy =
      std::sin(turn) * 1.3 + std::cos(turn) * 0.8 + m.at("translation")[1].get<double>();
  const json& moved = w.at("placement");
  EXPECT_NEAR(moved.at("center")[0].get<double>(), cx, 1e-12);
  EXPECT_NEAR(moved.at("center")[1].get<double>(), cy, 1e-12);
  EXPECT_NEAR(moved.at("rotation_deg").get<double>(), 20 + m.at("rotation_deg").get<double>(),
              1e-12);
  // The answer is the one for the moved placement, by the new surface's id.
  const std::string moved_placement = R"({"center":)" + moved.at("center").dump() +
                                      R"(,"rotation_deg":)" + moved.at("rotation_deg").dump() +
                                      R"(,"scale":1})";
  auto by_id = deform(R"("surface_id":")" + stats.at("surface_id").get<std::string>() + "\"",
                      moved_placement);
  ASSERT_TRUE(by_id);
  EXPECT_TRUE(by_id->body == edit->body);
  EXPECT_EQ(by_id->get_header_value("ETag"), edit->get_header_value("ETag"));
  // The model stayed where it was on the surface: nearer than the same
  // placement read on the new sheet's own frame.
  auto unmoved = deform(after, asked);
  ASSERT_TRUE(unmoved);
  const auto was = ObjCentroid(on_before->body);
  EXPECT_LT(Distance(ObjCentroid(edit->body), was),
            0.5 * Distance(ObjCentroid(unmoved->body), was));
  // An unknown start: a cold flattening, the placement as given.
  auto cold = deform(after + R"(,"warm_start":")" + std::string(kUnknown) + "\"", asked);
  ASSERT_TRUE(cold);
  EXPECT_TRUE(cold->body == unmoved->body);
  const json cold_start =
      json::parse(cold->get_header_value("X-Surfdeform-Stats")).at("warm_start");
  EXPECT_EQ(cold_start.at("used"), false);
  EXPECT_FALSE(cold_start.contains("placement"));
  // Only an inline surface is flattened from a start.
  json p = Problem(c.Post("/v1/deform",
                          R"({"model_id":")" + model + R"(","surface_id":")" + from +
                              R"(","warm_start":")" + from + "\"}",
                          "application/json"),
                   400, "malformed");
  EXPECT_EQ(p.value("field", ""), "warm_start");
}

}  // namespace
}  // namespace surfdeform::testing
