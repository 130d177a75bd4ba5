// Answers kept and meshopt GLB on the real server: a repeated
// POST /v1/deform is answered byte for byte from the kept answers (the
// metrics count it), its ETag is the answer's key, so If-None-Match gets 304
// with no body, and --answer-cache-mib 0 keeps nothing. The meshopt GLB
// comes with its media type and compression in the stats.
#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>

#include "server_process.hpp"
#include "shared_server.hpp"

namespace surfdeform::testing {
namespace {

using nlohmann::json;

const char kSurface[] =
    R"("surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},"sampling":{"nu":16,"nv":16})";

httplib::Client ClientOf(int port) {
  httplib::Client c("127.0.0.1", port);
  c.set_read_timeout(60, 0);
  return c;
}

std::string Bunny(httplib::Client& c) {
  auto r = c.Get("/samples/bunny.ply");
  EXPECT_TRUE(r && r->status == 200);
  return r ? r->body : std::string();
}

// The bunny by id on the cylinder, at `scale`, in `output`.
std::string ByIdParams(const std::string& model_id, const std::string& output, double scale = 0.6) {
  std::string p = R"({"model_id":")";
  p += model_id;
  p += "\",";
  p += kSurface;
  p += R"(,"placement":{"scale":)";
  p += std::to_string(scale);
  p += R"(},"output":)";
  p += output;
  p += "}";
  return p;
}

std::string Upload(httplib::Client& c, const std::string& mesh) {
  auto up = c.Post("/v1/models", mesh, "application/octet-stream");
  EXPECT_TRUE(up && (up->status == 201 || up->status == 200));
  return up ? json::parse(up->body).value("id", "") : "";
}

class AnswersTest : public SharedServerTest<AnswersTest> {
 public:
  static std::vector<std::string> Args() { return {"--log-level", "warn"}; }
};

TEST_F(AnswersTest, ARepeatedDeformIsAnsweredFromTheKeptAnswersAndIfNoneMatchIs304) {
  auto c = ClientOf(port());
  const std::string id = Upload(c, Bunny(c));
  const std::string params = ByIdParams(id, R"({"compression":"meshopt"})");
  const double hits = ScrapeMetric(port(), "surfdeform_answer_cache_hits_total");
  auto made = c.Post("/v1/deform", params, "application/json");
  ASSERT_TRUE(made);
  ASSERT_EQ(made->status, 200) << made->body;
  EXPECT_EQ(made->get_header_value("Content-Type"), "model/gltf-binary");
  const json stats = json::parse(made->get_header_value("X-Surfdeform-Stats"));
  EXPECT_EQ(stats.value("compression", ""), "meshopt");
  EXPECT_FALSE(stats.contains("answer_kept"));
  EXPECT_NE(made->body.find("EXT_meshopt_compression"), std::string::npos);
  const std::string etag = made->get_header_value("ETag");
  ASSERT_EQ(etag.size(), 34u);

  auto kept = c.Post("/v1/deform", params, "application/json");
  ASSERT_TRUE(kept);
  ASSERT_EQ(kept->status, 200);
  EXPECT_EQ(kept->body, made->body);
  EXPECT_EQ(kept->get_header_value("ETag"), etag);
  EXPECT_TRUE(
      json::parse(kept->get_header_value("X-Surfdeform-Stats")).value("answer_kept", false));
  EXPECT_EQ(ScrapeMetric(port(), "surfdeform_answer_cache_hits_total"), hits + 1);

  auto not_modified = c.Post("/v1/deform", {{"If-None-Match", etag}}, params, "application/json");
  ASSERT_TRUE(not_modified);
  EXPECT_EQ(not_modified->status, 304);
  EXPECT_TRUE(not_modified->body.empty());
  EXPECT_EQ(not_modified->get_header_value("ETag"), etag);
  EXPECT_EQ(ScrapeMetric(port(), "surfdeform_answer_cache_hits_total"), hits + 1)
      << "304 before the kept answers are looked at";

  // The same answer for the mesh sent inline: one key.
  json inline_params = json::parse(params);
  inline_params.erase("model_id");
  const httplib::MultipartFormDataItems form = {
      {"mesh", Bunny(c), "bunny.ply", "application/octet-stream"},
      {"params", inline_params.dump(), "", "application/json"}};
  auto sent = c.Post("/v1/deform", form);
  ASSERT_TRUE(sent);
  ASSERT_EQ(sent->status, 200) << sent->body;
  EXPECT_EQ(sent->get_header_value("ETag"), etag);
  EXPECT_EQ(sent->body, made->body);
}

TEST_F(AnswersTest, AnswersThatCompressComeGzippedToWhoAcceptsIt) {
  auto c = ClientOf(port());
  const std::string id = Upload(c, Bunny(c));
  // meshopt (and OBJ, PLY, plain GLB) compress; Draco does not.
  const std::string meshopt = ByIdParams(id, R"({"compression":"meshopt"})", 0.55);
  auto identity =
      c.Post("/v1/deform", {{"Accept-Encoding", "identity"}}, meshopt, "application/json");
  auto gzipped = c.Post("/v1/deform", {{"Accept-Encoding", "gzip"}}, meshopt, "application/json");
  ASSERT_TRUE(identity && gzipped);
  ASSERT_EQ(identity->status, 200) << identity->body;
  ASSERT_EQ(gzipped->status, 200) << gzipped->body;
  EXPECT_FALSE(identity->has_header("Content-Encoding"));
  EXPECT_EQ(gzipped->get_header_value("Content-Encoding"), "gzip");
  EXPECT_EQ(gzipped->get_header_value("Vary"), "Accept-Encoding");
  EXPECT_EQ(gzipped->body, identity->body) << "the client inflated it to the same bytes";
  const std::string etag = identity->get_header_value("ETag");
  EXPECT_EQ(gzipped->get_header_value("ETag"), etag.substr(0, etag.size() - 1) + "-gzip\"");
  auto not_modified =
      c.Post("/v1/deform",
             {{"Accept-Encoding", "gzip"}, {"If-None-Match", gzipped->get_header_value("ETag")}},
             meshopt, "application/json");
  ASSERT_TRUE(not_modified);
  EXPECT_EQ(not_modified->status, 304);

  const std::string draco = ByIdParams(id, R"({"format":"glb"})", 0.55);
  auto plain = c.Post("/v1/deform", {{"Accept-Encoding", "gzip"}}, draco, "application/json");
  ASSERT_TRUE(plain);
  ASSERT_EQ(plain->status, 200);
  EXPECT_FALSE(plain->has_header("Content-Encoding")) << "Draco does not compress";
}

TEST_F(AnswersTest, InfoAndMetricsPublishTheBudget) {
  auto c = ClientOf(port());
  auto info = c.Get("/v1/info");
  ASSERT_TRUE(info && info->status == 200);
  EXPECT_EQ(json::parse(info->body).at("limits").value("answer_cache_bytes", 0.0),
            256.0 * (1 << 20));
  EXPECT_EQ(ScrapeMetric(port(), "surfdeform_answer_cache_capacity_bytes"), 256.0 * (1 << 20));
  const json compressions = json::parse(info->body).at("enums").at("output.compression");
  ASSERT_EQ(compressions.size(), 3u);
  EXPECT_EQ(compressions[0].value("name", ""), "draco");
}

TEST(AnswersOff, ABudgetOfZeroKeepsNothing) {
  ServerProcess server(ServerBinary(), {"--log-level", "warn", "--answer-cache-mib", "0"});
  ASSERT_GT(server.port(), 0);
  auto c = ClientOf(server.port());
  const std::string id = Upload(c, Bunny(c));
  const std::string params = ByIdParams(id, R"({"format":"drc"})");
  std::string first;
  for (int k = 0; k < 2; ++k) {
    auto r = c.Post("/v1/deform", params, "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_FALSE(json::parse(r->get_header_value("X-Surfdeform-Stats")).contains("answer_kept"));
    if (k == 0) first = r->body;
    EXPECT_EQ(r->body, first);
  }
  EXPECT_EQ(ScrapeMetric(server.port(), "surfdeform_answer_cache_hits_total"), 0.0);
  EXPECT_EQ(ScrapeMetric(server.port(), "surfdeform_answer_cache_capacity_bytes"), 0.0);
}

}  // namespace
}  // namespace surfdeform::testing
