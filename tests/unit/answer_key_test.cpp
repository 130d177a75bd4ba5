// The key of a kept answer (proto/answer_key.hpp): equal requests, however
// written, have one key; any change that changes the bytes changes it.
#include "proto/answer_key.hpp"

#include <gtest/gtest.h>

#include <set>

namespace surfdeform::proto {
namespace {

using nlohmann::json;

// The key of these deform parameters for model "m" on surface "s".
std::string KeyOf(const std::string& params, OutputFormat format = OutputFormat::kDrc) {
  auto p = ParseDeformParams(json::parse(params));
  EXPECT_TRUE(p.ok()) << p.status().ToString();
  if (!p.ok()) return "";
  const OutputFormat chosen = p->output.format.value_or(format);
  return AnswerKey({"m", "s", &p->placement, &p->subdivision, &p->output, chosen});
}

constexpr char kId[] = R"("surface_id":"0123456789abcdef0123456789abcdef")";

// {<fields>, "surface_id": ...} (built with += : GCC 12 misreads
// operator+ chains here as overlapping copies, -Wrestrict).
std::string WithId(const char* fields = "") {
  std::string text = "{";
  text += fields;
  text += kId;
  text += "}";
  return text;
}

TEST(AnswerKey, EqualRequestsHaveOneKeyHoweverWritten) {
  const std::string bare = KeyOf(WithId());
  // Defaults spelled out, in another order.
  EXPECT_EQ(KeyOf(WithId(R"("output":{"format":"drc","distortion":false},)"
                         R"("subdivision":{"mode":"adaptive"},"placement":{"up":"auto",)"
                         R"("anchor":"center","center":"center","rotation_deg":0,"scale":1,)"
                         R"("outside":"error"},)")),
            bare);
  // The format from the Accept header or from the parameters.
  EXPECT_EQ(KeyOf(WithId(), OutputFormat::kGlb), KeyOf(WithId(R"("output":{"format":"glb"},)")));
  // meshopt names glb.
  EXPECT_EQ(KeyOf(WithId(R"("output":{"compression":"meshopt"},)")),
            KeyOf(WithId(R"("output":{"format":"glb","compression":"meshopt"},)")));
  // Draco's options are a Draco answer's.
  EXPECT_NE(KeyOf(WithId(R"("output":{"draco":{"position_bits":12}},)")), bare);
}

TEST(AnswerKey, EveryChangeThatChangesTheBytesChangesTheKey) {
  const std::vector<std::string> variants = {
      WithId(),
      WithId(R"("placement":{"scale":0.5},)"),
      WithId(R"("placement":{"scale":"fit"},)"),
      WithId(R"("placement":{"scale":"fit","fit_margin":0.1},)"),
      WithId(R"("placement":{"rotation_deg":10},)"),
      WithId(R"("placement":{"center":[1,2]},)"),
      WithId(R"("placement":{"center":{"fraction":[1,2]}},)"),
      WithId(R"("placement":{"anchor":0.25},)"),
      WithId(R"("placement":{"anchor":"top"},)"),
      WithId(R"("placement":{"up":"+y"},)"),
      WithId(R"("placement":{"rigid":"components"},)"),
      WithId(R"("placement":{"outside":"clamp"},)"),
      WithId(R"("subdivision":{"mode":"off"},)"),
      WithId(R"("subdivision":{"tolerance":0.01},)"),
      WithId(R"("subdivision":{"epsilon":0.5},)"),
      WithId(R"("output":{"format":"ply"},)"),
      WithId(R"("output":{"format":"ply","distortion":true},)"),
      WithId(R"("output":{"format":"glb"},)"),
      WithId(R"("output":{"format":"glb_plain"},)"),
      WithId(R"("output":{"compression":"meshopt"},)"),
      WithId(R"("output":{"compression":"none"},)"),
      WithId(R"("output":{"draco":{"speed":3}},)"),
      WithId(R"("output":{"draco":{"sequential":true}},)"),
  };

  std::set<std::string> keys;
  for (const std::string& v : variants) keys.insert(KeyOf(v));
  EXPECT_EQ(keys.size(), variants.size());
  // The model and the sheet are in it.
  auto p = ParseDeformParams(json::parse(WithId()));
  ASSERT_TRUE(p.ok());
  const std::string a =
      AnswerKey({"m", "s", &p->placement, &p->subdivision, &p->output, OutputFormat::kDrc});
  EXPECT_NE(AnswerKey({"n", "s", &p->placement, &p->subdivision, &p->output, OutputFormat::kDrc}),
            a);
  EXPECT_NE(AnswerKey({"m", "t", &p->placement, &p->subdivision, &p->output, OutputFormat::kDrc}),
            a);
  EXPECT_EQ(AnswerEtag(a).size(), 32u);
  EXPECT_NE(AnswerEtag(a), AnswerEtag(KeyOf(variants[1])));
}

TEST(AnswerKey, IfNoneMatchNamesAnEtagInAListWeakOrGzipped) {
  const std::string etag = "0123456789abcdef0123456789abcdef";
  EXPECT_TRUE(IfNoneMatchNames("\"" + etag + "\"", etag));
  EXPECT_TRUE(IfNoneMatchNames("\"other\", W/\"" + etag + "\"", etag));
  EXPECT_FALSE(IfNoneMatchNames(" * ", etag)) << "no answer is known before its key";
  EXPECT_TRUE(IfNoneMatchNames("\"" + etag + "-gzip\"", etag));  // the gzipped representation
  EXPECT_FALSE(IfNoneMatchNames("\"" + etag + "-br\"", etag));
  EXPECT_FALSE(IfNoneMatchNames("", etag));
  EXPECT_FALSE(IfNoneMatchNames(etag, etag));  // unquoted: not an entity tag
  const std::string shorter = "\"123456789abcdef0123456789abcdef\"";
  EXPECT_FALSE(IfNoneMatchNames(shorter, etag));
  EXPECT_FALSE(IfNoneMatchNames("\"x\"", ""));
}

}  // namespace
}  // namespace surfdeform::proto
