// POST /v1/parts on the real server: a ring grown from a whole cylinder
// comes back as a closed solid in millimetres, as 3MF (lib3mf's reader finds
// one object, unit millimetre), binary STL (as many triangles as the report
// says, read back by the server's own importer) or GLB; its report, in the
// stats header and with ?report=json, has the annulus's volume and the
// checks it passed. A surface by id gives the same part. Hostile or
// impossible bodies are each their own problem: a pole, a thickness past
// the surface's curvature (with the largest possible), a wall under the
// printer's minimum with strict (with the limit and the wall).
#include <gtest/gtest.h>
#include <httplib.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "print_files.hpp"
#include "shared_server.hpp"

namespace surfdeform::testing {
namespace {

using nlohmann::json;

// The ring of 18 mm inside, 6 mm wide, 1.8 mm thick.
json Ring(json more = json::object()) {
  json r = {{"surface", {{"kind", "cylinder"}, {"radius", 9}, {"height", 6}, {"angle_deg", 360}}},
            {"body", {{"thickness_mm", 1.8}, {"side", "outside"}}}};
  r.update(more);
  return r;
}
const double kAnnulus = std::numbers::pi * (10.8 * 10.8 - 9.0 * 9.0) * 6.0;

class ServerParts : public SharedServerTest<ServerParts> {
 public:
  // A memory budget a 512 x 512 body (1M triangles, ~256 MiB) is over.
  static std::vector<std::string> Args() { return {"--request-memory-mib", "128"}; }

 protected:
  static httplib::Result Part(const json& body, const std::string& query = "",
                              const httplib::Headers& headers = {}) {
    httplib::Client c("127.0.0.1", port());
    c.set_read_timeout(120, 0);
    return c.Post("/v1/parts" + query, headers, body.dump(), "application/json");
  }
  static json Stats(const httplib::Result& r) {
    return json::parse(r->get_header_value("X-Surfdeform-Stats"), nullptr, false);
  }
  static json ExpectProblem(const httplib::Result& r, int status, const std::string& field,
                            const std::string& says) {
    EXPECT_TRUE(r);
    if (!r) return json();
    EXPECT_EQ(r->status, status) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    json p = json::parse(r->body, nullptr, false);
    EXPECT_EQ(p.value("field", ""), field) << r->body;
    EXPECT_NE(p.value("detail", "").find(says), std::string::npos) << r->body;
    return p;
  }
};

TEST_F(ServerParts, ARingComesAsAClosed3mfInMillimetresByDefault) {
  auto r = Part(Ring());
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "model/3mf");
  const PrintFile contents = Read3mf(r->body);
  ASSERT_TRUE(contents.error.empty()) << contents.error;
  EXPECT_EQ(contents.unit, "millimeter");
  EXPECT_EQ(contents.objects, 1u);
  EXPECT_EQ(contents.build_items, 1u);
  const json s = Stats(r);
  EXPECT_EQ(contents.triangles, s.value("triangles", 0u)) << s;
  EXPECT_EQ(contents.vertices, s.value("vertices", 0u)) << s;
  EXPECT_EQ(s["units"], "mm");
  EXPECT_TRUE(s["checks"]["closed"].get<bool>()) << s;
  EXPECT_TRUE(s["checks"]["oriented"].get<bool>()) << s;
  EXPECT_FALSE(s["checks"]["self_intersections"].get<bool>()) << s;
  EXPECT_NEAR(s["volume_mm3"].get<double>(), kAnnulus, 5e-3 * kAnnulus) << s;
  EXPECT_NEAR(s["bounding_box_mm"]["size"][0].get<double>(), 21.6, 1e-6) << s;
  EXPECT_EQ(s["thinnest_wall_mm"], 1.8);
}

TEST_F(ServerParts, TheStlHasTheReportsTrianglesAndTheReportComesAsJson) {
  auto r = Part(Ring(), "", {{"Accept", "model/stl"}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "model/stl");
  const json s = Stats(r);
  ASSERT_GE(r->body.size(), 84u);
  uint32_t count = 0;
  std::memcpy(&count, r->body.data() + 80, 4);
  EXPECT_EQ(count, s.value("triangles", 0u));
  EXPECT_EQ(r->body.size(), 84 + 50 * static_cast<size_t>(count));
  const PrintFile read = ReadMeshFile(r->body);
  ASSERT_TRUE(read.error.empty()) << read.error;
  EXPECT_EQ(read.format, "stl");
  EXPECT_EQ(read.triangles, count);

  auto report = Part(Ring(), "?report=json");
  ASSERT_TRUE(report);
  ASSERT_EQ(report->status, 200) << report->body;
  EXPECT_EQ(report->get_header_value("Content-Type"), "application/json");
  const json j = json::parse(report->body);
  EXPECT_EQ(j["volume_mm3"], s["volume_mm3"]);
  EXPECT_EQ(j["triangles"], s["triangles"]);

  auto glb = Part(Ring({{"output", {{"format", "glb"}}}}));
  ASSERT_TRUE(glb);
  EXPECT_EQ(glb->status, 200);
  EXPECT_EQ(glb->get_header_value("Content-Type"), "model/gltf-binary");
}

TEST_F(ServerParts, ASurfaceByIdGivesTheSamePart) {
  httplib::Client c("127.0.0.1", port());
  auto made = c.Post("/v1/surfaces", Ring()["surface"].dump().insert(0, "{\"surface\":") + "}",
                     "application/json");
  ASSERT_TRUE(made);
  ASSERT_EQ(made->status, 201) << made->body;
  const std::string id = json::parse(made->body).value("id", "");
  json by_id = Ring();
  by_id.erase("surface");
  by_id["surface_id"] = id;
  auto a = Part(by_id, "?report=json"), b = Part(Ring(), "?report=json");
  ASSERT_TRUE(a && b);
  ASSERT_EQ(a->status, 200) << a->body;
  const json ja = json::parse(a->body), jb = json::parse(b->body);
  EXPECT_EQ(ja["surface_id"], id);
  EXPECT_EQ(ja["volume_mm3"], jb["volume_mm3"]);
}

TEST_F(ServerParts, ImpossibleBodiesAreEachTheirOwnProblem) {
  // A pole: a whole sphere has no normal at its ends.
  ExpectProblem(Part(Ring({{"surface",
                            {{"kind", "sphere"},
                             {"radius", 5},
                             {"lon_min_deg", 0},
                             {"lon_max_deg", 360},
                             {"lat_min_deg", -90},
                             {"lat_max_deg", 90}}}})),
                422, "surface", "no normal");
  // Inward past the radius: the inner face would fold.
  json p = ExpectProblem(Part(Ring({{"body", {{"thickness_mm", 10}, {"side", "inside"}}}})), 422,
                         "body.thickness_mm", "folds over itself");
  EXPECT_NEAR(p.value("limit", 0.0), 0.95 * 9, 1e-6) << p;
  EXPECT_EQ(p.value("actual", 0.0), 10.0) << p;
  // A wall under the printer's minimum: a warning, and with strict a 422.
  auto thin = Part(Ring({{"body", {{"thickness_mm", 0.5}}}, {"printer", {{"min_wall_mm", 0.8}}}}),
                   "?report=json");
  ASSERT_TRUE(thin);
  ASSERT_EQ(thin->status, 200) << thin->body;
  const json w = json::parse(thin->body)["warnings"];
  ASSERT_EQ(w.size(), 1u) << w;
  EXPECT_NE(w[0].get<std::string>().find("thinner than the printer's minimum of 0.8 mm"),
            std::string::npos);
  p = ExpectProblem(Part(Ring({{"body", {{"thickness_mm", 0.5}}},
                               {"printer", {{"min_wall_mm", 0.8}}},
                               {"strict", true}})),
                    422, "body.thickness_mm", "strict");
  EXPECT_EQ(p.value("limit", 0.0), 0.8) << p;
  EXPECT_EQ(p.value("actual", 0.0), 0.5) << p;
  // No thickness, a negative one, a field the route does not know.
  ExpectProblem(Part(Ring({{"body", {{"side", "inside"}}}})), 400, "body.thickness_mm", "required");
  ExpectProblem(Part(Ring({{"body", {{"thickness_mm", -1}}}})), 422, "body.thickness_mm",
                "more than 0");
  ExpectProblem(Part(Ring(), "?report=xml"), 422, "report", "must be \"json\"");
  // Refused before it runs: the body's estimate over the memory budget.
  p = ExpectProblem(Part(Ring({{"sampling", {{"nu", 512}, {"nv", 512}}}})), 413, "sampling",
                    "memory budget");
  EXPECT_EQ(p.value("limit", 0.0), 128.0 * 1024 * 1024) << p;
}

// The ring's STL uploaded as a model is a body as it is: the same volume;
// an open mesh is a 422 counting its border edges and saying where.
TEST_F(ServerParts, AnUploadedBodyIsCheckedAndSentAsItIs) {
  httplib::Client c("127.0.0.1", port());
  auto stl = Part(Ring({{"output", {{"format", "stl"}}}}));
  ASSERT_TRUE(stl);
  ASSERT_EQ(stl->status, 200) << stl->body;
  auto up = c.Post("/v1/models", stl->body, "application/octet-stream");
  ASSERT_TRUE(up);
  ASSERT_TRUE(up->status == 200 || up->status == 201) << up->body;
  const std::string id = json::parse(up->body).value("id", "");
  auto uploaded = Part({{"body", {{"model_id", id}}}}, "?report=json");
  ASSERT_TRUE(uploaded);
  ASSERT_EQ(uploaded->status, 200) << uploaded->body;
  const json r = json::parse(uploaded->body);
  const double grown = Stats(stl)["volume_mm3"].get<double>();
  EXPECT_NEAR(r["volume_mm3"].get<double>(), grown, 5e-3 * grown) << r;
  EXPECT_TRUE(r["checks"]["closed"].get<bool>()) << r;
  EXPECT_EQ(r["body"]["model_id"], id);
  EXPECT_TRUE(r["thinnest_wall_mm"].is_null()) << r;
  auto as_3mf = Part({{"body", {{"model_id", id}}}});
  ASSERT_TRUE(as_3mf);
  EXPECT_EQ(as_3mf->status, 200);
  EXPECT_EQ(Read3mf(as_3mf->body).unit, "millimeter");

  // A flat square of two triangles: four border edges.
  const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
  auto open = c.Post("/v1/models", square, "application/octet-stream");
  ASSERT_TRUE(open);
  const std::string open_id = json::parse(open->body).value("id", "");
  json p = ExpectProblem(Part({{"body", {{"model_id", open_id}}}}), 422, "body.model_id",
                         "4 edges border one triangle only (near (0, 0.5, 0)");
  EXPECT_EQ(p.value("actual", 0), 4) << p;
  ExpectProblem(Part({{"body", {{"model_id", std::string(32, 'a')}}}}), 404, "body.model_id", "");
  ExpectProblem(Part({{"body", {{"model_id", id}, {"thickness_mm", 2}}}}), 400, "body.thickness_mm",
                "belongs to a body grown from a surface");
  ExpectProblem(Part(Ring({{"body", {{"model_id", id}}}})), 400, "surface", "used as it is");
}

}  // namespace
}  // namespace surfdeform::testing
