// Text as a model, against the real server: the built-in fonts and their
// scripts, a name round the bottle sample with rigid glyphs, an uploaded
// font used by its id, and every refusal with its problem (the suites'
// names begin with "Server": CI runs them against the sanitized server too).
#include <gtest/gtest.h>
#include <httplib.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "server_process.hpp"
#include "shared_server.hpp"

namespace surfdeform::testing {
namespace {

using json = nlohmann::json;

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

json Bottle() {
  json b = json::parse(ReadFile(SURFDEFORM_SOURCE_DIR "/client/web/samples/bottle.json"));
  b.erase("description");
  return b;
}

class ServerText : public SharedServerTest<ServerText> {
 public:
  static std::vector<std::string> Args() { return {}; }

 protected:
  static httplib::Client Client() {
    httplib::Client c("127.0.0.1", port());
    c.set_read_timeout(120, 0);
    return c;
  }
  static httplib::Result Deform(const json& params) {
    auto c = Client();
    return c.Post("/v1/deform", params.dump(), "application/json");
  }
  static json Name(const std::string& text, json more = json::object()) {
    json t = {{"string", text}, {"size_mm", 0.5}, {"depth_mm", 0.05}};
    t.update(more);
    return {{"surface", Bottle()},
            {"text", t},
            {"placement", {{"rigid", "components"}}},
            {"output", {{"format", "obj"}}}};
  }
  static void ExpectProblem(const httplib::Result& r, int status, const std::string& field,
                            const std::string& says) {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    const json p = json::parse(r->body, nullptr, false);
    EXPECT_EQ(p.value("field", ""), field) << r->body;
    EXPECT_NE(p.value("detail", "").find(says), std::string::npos) << r->body;
  }
};

TEST_F(ServerText, BuiltinFontsCoverTheirScripts) {
  auto c = Client();
  auto r = c.Get("/v1/fonts");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json list = json::parse(r->body);
  std::set<std::string> covered;
  std::set<std::string> names;
  for (const json& f : list["fonts"]) {
    names.insert(f["name"].get<std::string>());
    for (const json& s : f["scripts"]) covered.insert(s.get<std::string>());
    EXPECT_GT(f["glyphs"].get<int>(), 100);
  }
  for (const char* n :
       {"DejaVuSans", "DejaVuSerif", "DejaVuSansMono", "Amiri", "EzraSIL", "LohitDevanagari"}) {
    EXPECT_EQ(names.count(n), 1u) << n << " missing: " << list["missing"];
  }
  for (const char* s : {"Latn", "Grek", "Cyrl", "Arab", "Hebr", "Deva"}) {
    EXPECT_EQ(covered.count(s), 1u) << s;
  }
  auto info = c.Get("/v1/info");
  ASSERT_TRUE(info);
  const json limits = json::parse(info->body)["font_limits"];
  for (const char* k : {"max_font_bytes", "max_glyphs", "max_glyph_points", "max_text_cost"}) {
    EXPECT_GT(limits.value(k, 0.0), 0.0) << k;
  }
}

TEST_F(ServerText, ANameRoundTheBottleWithRigidGlyphs) {
  auto r = Deform(Name("Ada Lovelace"));
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json stats = json::parse(r->get_header_value("X-Surfdeform-Stats"));
  EXPECT_EQ(stats["text"]["glyphs"], 12);
  EXPECT_EQ(stats["text"]["solids"], 11);
  EXPECT_EQ(stats["text"]["clusters"][0]["text"], "A");
  EXPECT_EQ(stats["rigid"]["parts"], 11);
  EXPECT_EQ(stats["placement"]["up"], "+z");
  EXPECT_GT(stats["placement"]["turns"].get<double>(), 0.3);  // round the bottle
  // The OBJ has the solids' vertices and faces.
  size_t v = 0, f = 0;
  std::istringstream obj(r->body);
  for (std::string line; std::getline(obj, line);) {
    v += line.rfind("v ", 0) == 0;
    f += line.rfind("f ", 0) == 0;
  }
  EXPECT_EQ(v, stats["vertices"].get<size_t>());
  EXPECT_EQ(f, stats["triangles"].get<size_t>());
  // The same text again is the same answer (its key is the text and the font).
  auto again = Deform(Name("Ada Lovelace"));
  ASSERT_TRUE(again);
  EXPECT_EQ(again->get_header_value("ETag"), r->get_header_value("ETag"));
  auto other = Deform(Name("Ada Lovelacf"));
  ASSERT_TRUE(other);
  EXPECT_NE(other->get_header_value("ETag"), r->get_header_value("ETag"));
}

// A long text's stats keep within the header's bound (nginx answers 502 past
// its 4 KB of headers): its clusters are cut to their first ones, and
// "clusters_omitted" counts the rest. The same for POST /v1/text.
TEST_F(ServerText, ALongTextsStatsKeepWithinTheHeadersBound) {
  const std::string words = "The quick brown fox jumps over the lazy dog, twice over";
  json params = Name(words, {{"size_mm", 1}, {"depth_mm", 0.1}});
  params["surface"] = {{"kind", "cylinder"}, {"radius", 20}, {"height", 10}, {"angle_deg", 360}};
  auto r = Deform(params);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const std::string header = r->get_header_value("X-Surfdeform-Stats");
  EXPECT_LE(header.size(), 2048u);
  const json stats = json::parse(header);
  const size_t kept = stats["text"]["clusters"].size();
  EXPECT_GT(kept, 0u);
  EXPECT_EQ(stats["text"]["clusters"][0]["text"], "T");  // the first ones kept
  EXPECT_EQ(kept + stats["text"].value("clusters_omitted", size_t{0}),
            stats["text"]["glyphs"].get<size_t>());
  EXPECT_GT(stats["text"].value("clusters_omitted", size_t{0}), 0u);

  auto c = Client();
  auto alone = c.Post(
      "/v1/text",
      json({{"text", {{"string", words}, {"size_mm", 1}}}, {"output", {{"format", "obj"}}}}).dump(),
      "application/json");
  ASSERT_TRUE(alone);
  ASSERT_EQ(alone->status, 200) << alone->body;
  EXPECT_LE(alone->get_header_value("X-Surfdeform-Stats").size(), 2048u);
}

TEST_F(ServerText, ANameSwimsWithTheWave) {
  json params = json::parse(ReadFile(SURFDEFORM_SOURCE_DIR "/client/web/samples/swim.json"));
  params["animation"]["frames"] = 4;
  params["text"] = {{"string", "Ada"}, {"size_mm", 0.4}, {"depth_mm", 0.03}};
  auto c = Client();
  auto r = c.Post("/v1/animate", params.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->body.substr(0, 4), "glTF");
  const json stats = json::parse(r->get_header_value("X-Surfdeform-Stats"));
  EXPECT_EQ(stats["frames"], 4) << stats.dump();
  EXPECT_EQ(stats["text"]["solids"], 3);
  // The flat mesh alone: POST /v1/text, in mm, the baseline's centre at the
  // origin; one OBJ material per glyph.
  auto flat = c.Post("/v1/text",
                     json{{"text", {{"string", "Ada"}}}, {"output", {{"format", "obj"}}}}.dump(),
                     "application/json");
  ASSERT_TRUE(flat);
  ASSERT_EQ(flat->status, 200) << flat->body;
  size_t groups = 0;
  double lo = 1e9, hi = -1e9;
  std::istringstream obj(flat->body);
  for (std::string line; std::getline(obj, line);) {
    groups += line.rfind("usemtl ", 0) == 0;  // one material per glyph, named by it
    if (line.rfind("v ", 0) == 0) {
      std::istringstream v(line.substr(2));
      double x = 0;
      v >> x;
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  EXPECT_EQ(groups, 3u);
  EXPECT_NEAR(lo + hi, 0.0, 0.5);  // centred on the origin, within the side bearings
  EXPECT_GT(hi - lo, 4.0);         // "Ada" at a 4 mm em: some 7 mm long
}

TEST_F(ServerText, AnUploadedFontIsUsedByItsId) {
  const std::string amiri = ReadFile("/usr/share/fonts/opentype/fonts-hosny-amiri/Amiri-Bold.ttf");
  ASSERT_FALSE(amiri.empty());
  auto c = Client();
  auto up = c.Post("/v1/fonts", amiri, "font/ttf");
  ASSERT_TRUE(up);
  ASSERT_EQ(up->status, 201) << up->body;
  const json font = json::parse(up->body);
  EXPECT_EQ(font["family"], "Amiri");
  EXPECT_EQ(up->get_header_value("Location"), "/v1/fonts/" + font["id"].get<std::string>());
  auto r = Deform(Name("سلام", {{"font", font["id"]}}));
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json stats = json::parse(r->get_header_value("X-Surfdeform-Stats"));
  EXPECT_EQ(stats["text"]["family"], "Amiri");
  EXPECT_EQ(stats["text"]["runs"][0], "Arab rtl");
}

TEST_F(ServerText, RefusalsSayHowToFix) {
  ExpectProblem(Deform(Name("नमस्ते")), 422, "text.string", "LohitDevanagari");
  ExpectProblem(Deform(Name("Ada", {{"font", "NoSuchFont"}})), 422, "text.font", "DejaVuSans");
  ExpectProblem(Deform(Name("Ada", {{"size_mm", 0.1}})), 422, "text.size_mm", "0.32 mm");
  ExpectProblem(Deform(Name("Ada", {{"depth_mm", 0.001}})), 422, "text.depth_mm", "0.01 mm");
  ExpectProblem(Deform(Name("Ada Lovelace", {{"path", {{"sheet_points", {{0, 0}, {1, 0}}}}}})), 422,
                "text.path", "the path is 1 mm long");
  ExpectProblem(Deform(Name("Ada", {{"size", 4}})), 400, "text.size", "unknown field");
  json both = Name("Ada");
  both["model_id"] = std::string(32, 'a');
  ExpectProblem(Deform(both), 400, "model_id", "not both");
  // A broken font: a 400, and the server goes on.
  auto c = Client();
  std::string broken = ReadFile("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf").substr(0, 3000);
  ExpectProblem(c.Post("/v1/fonts", broken, "font/ttf"), 400, "font", "cannot be read");
  ExpectProblem(c.Post("/v1/fonts", std::string(100, 'x'), "font/ttf"), 400, "font",
                "cannot be read");
  auto alive = c.Get("/healthz");
  ASSERT_TRUE(alive);
  EXPECT_EQ(alive->status, 200);
}

}  // namespace
}  // namespace surfdeform::testing
