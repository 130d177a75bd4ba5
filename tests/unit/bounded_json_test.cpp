// Untrusted JSON read within limits (json/bounded_json.hpp): each limit stops
// the parse where it is passed and names the limit and the count; members
// to skip are never kept; the checkpoint stops the parse with its error.
#include "json/bounded_json.hpp"

#include <gtest/gtest.h>

#include <string>

namespace surfdeform {
namespace {

std::string Objects(size_t n) {
  std::string s = "{\"x\":[";
  for (size_t k = 0; k < n; ++k) s += k == 0 ? "{}" : ",{}";
  return s + "]}";
}

TEST(BoundedJson, ReadsWhatNlohmannReads) {
  const std::string text =
      R"({"a":[1,-2,3.5,1e300,"s",true,null,{"b":{}}],"c":{"d":"\u00e9"},"e":18446744073709551615})";
  auto r = ParseBoundedJson(text, JsonLimits{}, "body");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(*r, nlohmann::json::parse(text));
}

TEST(BoundedJson, ValuesPastTheLimitStopTheParseNamingWhere) {
  JsonLimits limits;
  limits.max_elements = 100;
  EXPECT_TRUE(ParseBoundedJson(Objects(98), limits, "body").ok());  // the root, x, 98 objects
  auto r = ParseBoundedJson(Objects(99), limits, "body");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(r.status().field(), "body.x");
  EXPECT_EQ(r.status().limit(), 100);
  EXPECT_EQ(r.status().actual(), 101);
}

TEST(BoundedJson, StringBytesPastTheLimitStopTheParse) {
  JsonLimits limits;
  limits.max_string_bytes = 10;
  EXPECT_TRUE(ParseBoundedJson(R"({"ab":"cdefghij"})", limits, "p").ok());
  auto r = ParseBoundedJson(R"({"ab":"cdefghijk"})", limits, "p");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(r.status().actual(), 11);
}

TEST(BoundedJson, DuplicateKeysAreFoundWithTheirPath) {
  auto r = ParseBoundedJson(R"({"a":[{"k":1},{"k":1,"k":2}]})", JsonLimits{}, "params");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kMalformed);
  EXPECT_EQ(r.status().field(), "params.a[1].k");
}

TEST(BoundedJson, SkippedMembersAreNeverKeptNorCounted) {
  JsonLimits limits;
  limits.max_elements = 6;
  limits.skip_member = [](std::string_view parent, std::string_view key) {
    return key == "extras" || (parent == "extensions" && key != "KEEP");
  };
  size_t skipped = 0;
  auto r = ParseBoundedJson(
      R"({"extras":[[1,2,[3]],{"x":{}}],"n":{"extras":"s"},"extensions":{"A":{"q":[1,2,3]},"KEEP":1,"B":"x"}})",
      limits, "gltf", {}, &skipped);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(*r, nlohmann::json::parse(R"({"n":{},"extensions":{"KEEP":1}})"));
  EXPECT_EQ(skipped, 4u);
  // Depth still counts inside what is skipped.
  limits.max_depth = 3;
  EXPECT_FALSE(ParseBoundedJson(R"({"extras":[[[[1]]]]})", limits, "gltf").ok());
}

TEST(BoundedJson, TheCheckpointStopsTheParseWithItsError) {
  int calls = 0;
  auto r = ParseBoundedJson(Objects(3 * kJsonCheckpointValues), JsonLimits{}, "body", [&] {
    return ++calls < 2 ? Status::Ok() : Status(ErrorCode::kUnavailable, "cancelled");
  });
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kUnavailable);
  EXPECT_EQ(calls, 2);
}

TEST(BoundedJson, SyntaxErrorsAndHugeNumbersAreNamed) {
  auto bad = ParseBoundedJson(R"({"a":[1,2})", JsonLimits{}, "body");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), ErrorCode::kMalformed);
  EXPECT_NE(bad.status().message().find("byte"), std::string::npos);
  auto huge = ParseBoundedJson(R"({"a":1e400})", JsonLimits{}, "body");
  ASSERT_FALSE(huge.ok());
  EXPECT_EQ(huge.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(ParseBoundedJson("{} {}", JsonLimits{}, "body").ok());  // one document only
}

}  // namespace
}  // namespace surfdeform
