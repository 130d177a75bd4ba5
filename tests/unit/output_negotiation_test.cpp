// Output format from parameters and the Accept header.
#include "service/output_negotiation.hpp"

#include <gtest/gtest.h>

namespace surfdeform {
namespace {

using proto::OutputFormat;

OutputFormat Chosen(std::string_view accept) {
  auto r = ChooseOutputFormat(std::nullopt, accept);
  EXPECT_TRUE(r.ok()) << accept;
  return r.ok() ? *r : OutputFormat::kDrc;
}

TEST(OutputNegotiation, AcceptHeader) {
  EXPECT_EQ(Chosen(""), OutputFormat::kDrc);
  EXPECT_EQ(Chosen("*/*"), OutputFormat::kDrc);
  EXPECT_EQ(Chosen("application/octet-stream"), OutputFormat::kDrc);
  EXPECT_EQ(Chosen("model/gltf-binary"), OutputFormat::kGlb);
  EXPECT_EQ(Chosen("Model/GLTF-Binary; q=0.9"), OutputFormat::kGlb);
  EXPECT_EQ(Chosen("text/html, model/obj;q=0.5"), OutputFormat::kObj);
  EXPECT_EQ(Chosen("application/x-ply"), OutputFormat::kPly);
  EXPECT_EQ(Chosen("model/gltf-binary;q=0, application/octet-stream"), OutputFormat::kDrc);
}

TEST(OutputNegotiation, ParametersWinAndUnknownTypesAreRefused) {
  auto r = ChooseOutputFormat(OutputFormat::kPly, "model/gltf-binary");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r, OutputFormat::kPly);
  r = ChooseOutputFormat(std::nullopt, "image/png, text/html");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kNotAcceptable);
  r = ChooseOutputFormat(std::nullopt, "model/gltf-binary;q=0");
  EXPECT_FALSE(r.ok());
}

TEST(OutputNegotiation, GlbOnlyAnswersReadTheSameHeader) {
  for (const char* ok : {"", "*/*", "model/gltf-binary", "MODEL/*;q=0.5",
                         "application/json;q=0.9, model/gltf-binary"}) {
    EXPECT_TRUE(AcceptGlbOnly(ok).ok()) << ok;
  }
  for (const char* refused : {"application/octet-stream", "model/gltf-binary;q=0",
                              "model/gltf-binary;q=0.0, text/plain", "application/x-ply"}) {
    const Status s = AcceptGlbOnly(refused);
    EXPECT_EQ(s.code(), ErrorCode::kNotAcceptable) << refused;
    EXPECT_EQ(s.field(), "Accept");
  }
}

TEST(OutputNegotiation, JsonOrBytesAnswersTakeTheFirstOfTheTwoAccepted) {
  for (const char* bytes : {"application/octet-stream", "Application/Octet-Stream",
                            "application/octet-stream, application/json",
                            "application/json;q=0, application/octet-stream"}) {
    EXPECT_TRUE(PrefersBytesToJson(bytes)) << bytes;
  }
  for (const char* text :
       {"", "*/*", "application/json", "application/json, application/octet-stream",
        "application/octet-stream;q=0", "image/png"}) {
    EXPECT_FALSE(PrefersBytesToJson(text)) << text;
  }
}

}  // namespace
}  // namespace surfdeform
