// The replies room alone: finite numbers only, the stats header's size cut,
// JSON replies and their ETags, a deformation's statistics, /v1/info.
#include "service/replies.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "service/limit_checks.hpp"
#include "support/test_meshes.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;

TEST(Replies, ANonFiniteNumberIsRefusedNamingItsPath) {
  const json ok = {{"a", 1.5}, {"b", {1, 2, 3}}};
  EXPECT_EQ(FirstNonFiniteNumber(ok), "");
  EXPECT_EQ(*DumpFinite(ok, "reply"), R"({"a":1.5,"b":[1,2,3]})");

  json bad = ok;
  bad["b"][1] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(FirstNonFiniteNumber(bad), "b[1]");
  bad["c"] = {{"d", std::nan("")}};
  auto refused = DumpFinite(bad, "statistics");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(refused.status().field(), "b[1]");
  EXPECT_NE(refused.status().message().find("statistics's b[1]"), std::string::npos);
  EXPECT_FALSE(JsonReply(bad).ok());
  EXPECT_FALSE(BoundedStats(bad).ok());
}

TEST(Replies, TheStatsHeaderCutsTheLongestListsToFitAndCountsTheCut) {
  json stats = {{"surface_id", "x"},
                {"rigid", {{"each", json::array()}}},
                {"frames", {{"each", json::array()}}}};
  for (int k = 0; k < 300; ++k) stats["rigid"]["each"].push_back({{"vertices", k}, {"lift", 0.5}});
  for (int k = 0; k < 10; ++k) stats["frames"]["each"].push_back(k);
  auto bounded = BoundedStats(stats);
  ASSERT_TRUE(bounded.ok());
  EXPECT_LE(StatsJsonText(*bounded).size(), kMaxStatsHeaderBytes);
  const json& cut = *bounded;
  const size_t kept = cut["rigid"]["each"].size();
  EXPECT_GT(kept, 10u);
  EXPECT_EQ(kept + cut["rigid"]["each_omitted"].get<size_t>(), 300u);
  EXPECT_EQ(cut["rigid"]["each"][0], stats["rigid"]["each"][0]);  // the first ones kept
  EXPECT_EQ(cut["frames"]["each"].size(), 10u);                   // the short list left alone
  EXPECT_FALSE(cut["frames"].contains("each_omitted"));

  // A text's clusters are such a list too.
  json text = {{"text", {{"glyphs", 200}, {"clusters", json::array()}}}};
  for (int k = 0; k < 200; ++k) text["text"]["clusters"].push_back({{"text", "a"}, {"s_mm", k}});
  auto text_bounded = BoundedStats(text);
  ASSERT_TRUE(text_bounded.ok());
  EXPECT_LE(StatsJsonText(*text_bounded).size(), kMaxStatsHeaderBytes);
  const json& clusters = (*text_bounded)["text"]["clusters"];
  EXPECT_GT(clusters.size(), 10u);
  EXPECT_EQ(clusters.size() + (*text_bounded)["text"]["clusters_omitted"].get<size_t>(), 200u);

  const json small = {{"surface_id", "x"}, {"rigid", {{"each", {1, 2}}}}};
  EXPECT_EQ(*BoundedStats(small), small);
}

TEST(Replies, AJsonReplyCarriesItsTypeAndAnETagOverItsBytes) {
  auto a = JsonReply({{"n", 1}});
  auto b = JsonReply({{"n", 1}});
  auto c = JsonReply({{"n", 2}});
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(a->content_type, "application/json");
  EXPECT_EQ(a->body, R"({"n":1})");
  EXPECT_EQ(a->etag.size(), 32u);
  EXPECT_EQ(a->etag, b->etag);
  EXPECT_NE(a->etag, c->etag);
}

TEST(Replies, ADeformationsStatisticsSayWhatWasReused) {
  ImportedMesh imported;
  imported.format = MeshFormat::kObj;
  imported.warnings = {"2 lines ignored"};
  DeformStats st;
  st.vertices = 8;
  st.triangles = 12;
  auto stats =
      DeformReplyStatsOf("abc", FlattenQuality{}, true, proto::OutputFormat::kPly, imported, st);
  stats->placement_reused = true;
  const json j = stats->ToJson();
  EXPECT_EQ(j["surface_id"], "abc");
  EXPECT_EQ(j["cached"], true);
  EXPECT_EQ(j["format"], "ply");
  EXPECT_EQ(j["input_format"], "obj");
  EXPECT_EQ(j["vertices"], 8);
  EXPECT_EQ(j["placement"]["reused"], true);
  EXPECT_EQ(j["subdivision"]["reused"], false);
  EXPECT_EQ(j["warnings"][0], "2 lines ignored");
  EXPECT_FALSE(j.contains("rigid"));
  EXPECT_FALSE(j.contains("distortion"));
}

TEST(Replies, InfoPublishesTheLimitsAsConfigured) {
  ServiceLimits limits;
  limits.max_grid_side = 77;
  limits.request_memory_bytes = 64u << 20;
  const json info = InfoJson(limits, Retention{});
  EXPECT_EQ(info["limits"]["max_grid_side"], 77);
  EXPECT_EQ(info["limits"]["request_memory_bytes"], 64u << 20);
  // The output limit shrinks to fit the memory budget: 64 MiB / 384 B.
  EXPECT_EQ(info["limits"]["max_output_vertices"], (64u << 20) / 384);
  // And the crossings the subdivision may keep to measure: 64 MiB / 128 B.
  EXPECT_EQ(info["limits"]["max_subdivision_crossings"], (64u << 20) / 128);
  EXPECT_EQ(info["limits"]["max_map_points"], kMapLimits.max_points);
  EXPECT_FALSE(info["enums"]["problem.code"].empty());
}

TEST(Replies, AMeshReplyIsTheFormatAskedForWithItsEncodingTimed) {
  ImportedMesh imported;
  imported.format = MeshFormat::kObj;
  proto::OutputOptions output;
  auto stats = std::make_shared<TextReplyStats>();
  stats->vertices = 8;
  stats->format = proto::OutputFormat::kObj;
  auto reply = MeshReply(testing::ThinPlate(1.0, 0.5, 0.05), output, proto::OutputFormat::kObj,
                         imported, false, {{"parse", 1.0}}, stats);
  ASSERT_TRUE(reply.ok()) << reply.status().ToString();
  EXPECT_EQ(reply->content_type, "model/obj");
  // Vertex lines, first or after another line.
  EXPECT_TRUE(reply->body.rfind("v ", 0) == 0 || reply->body.find("\nv ") != std::string::npos);
  ASSERT_EQ(reply->timings.size(), 2u);
  EXPECT_EQ(reply->timings[1].name, "encode");
  EXPECT_EQ(StatsHeaderText(*reply), R"({"format":"obj","triangles":0,"vertices":8})");
  // Served again from the kept answers: the header says so, the stats stay as made.
  Reply kept = *reply;
  MarkKept(&kept);
  EXPECT_EQ(StatsHeaderText(kept),
            R"({"answer_kept":true,"cached":true,"format":"obj","triangles":0,"vertices":8})");
  EXPECT_EQ(StatsHeaderText(*reply), R"({"format":"obj","triangles":0,"vertices":8})");
  EXPECT_TRUE(kept.timings.empty());
  EXPECT_EQ(reply->etag.size(), 32u);
}

}  // namespace
}  // namespace surfdeform
