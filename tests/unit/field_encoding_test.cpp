// The field's JSON text, written directly (service/field_encoding.hpp).
#include "service/field_encoding.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

namespace surfdeform {
namespace {

using nlohmann::json;

SheetField Field() {
  SheetField f;
  f.n = 2;
  f.lo = Vec2(-1.0, 0.1);
  f.hi = Vec2(2.5, 3.0);
  for (int k = 0; k < 4; ++k) {
    f.positions.emplace_back(0.1 * k, 1.0 / 3.0, -2e-7 * k);
    f.normals.emplace_back(0.0, k == 3 ? -1.0 : 0.6, 0.8);
    f.on_sheet.push_back(k == 2 ? 0 : 1);
    f.params.emplace_back(0.25 * k, 1.0 - 0.25 * k);
  }
  return f;
}

// Every number reads back as the float32 the bytes carry, in the shortest
// text that does; the layout is the documented one.
TEST(FieldEncoding, JsonTextReadsBackAsTheFloatsOfTheBytes) {
  const SheetField f = Field();
  auto text = FieldJsonText(f);
  ASSERT_TRUE(text.ok()) << text.status().ToString();
  const json j = json::parse(*text);
  EXPECT_EQ(j.at("n"), 2);
  EXPECT_EQ(j.at("bounds"), json::parse("[[-1,0.1],[2.5,3]]"));
  ASSERT_EQ(j.at("positions").size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(static_cast<float>(j["positions"][k][c].get<double>()),
                static_cast<float>(f.positions[k][c]));
      EXPECT_EQ(static_cast<float>(j["normals"][k][c].get<double>()),
                static_cast<float>(f.normals[k][c]));
    }
    for (int c = 0; c < 2; ++c) {
      EXPECT_EQ(static_cast<float>(j["params"][k][c].get<double>()),
                static_cast<float>(f.params[k][c]));
    }
    EXPECT_EQ(j["on_sheet"][k].get<bool>(), k != 2);
  }
  // The shortest text: 1/3 as a float is 0.33333334, and 0.1 is 0.1.
  EXPECT_NE(text->find("[0.1,0.33333334,-2e-07]"), std::string::npos) << *text;
  EXPECT_EQ(text->find(' '), std::string::npos);
}

// A number past float32's range is an error naming it, never "inf" text.
TEST(FieldEncoding, ANumberPastFloatRangeIsAnErrorNamingIt) {
  SheetField f = Field();
  f.positions[3].y() = 1e39;
  f.normals[1].x() = -1e300;  // the normals come first in the text
  auto text = FieldJsonText(f, "field");
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(text.status().field(), "field.normals[1][0]");
  f.normals[1].x() = 0.0;
  auto again = FieldJsonText(f);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.status().field(), "positions[3][1]");
  EXPECT_NE(again.status().message().find("finite"), std::string::npos);
}

TEST(FieldEncoding, AMemberIsAddedAtTheObjectsEnd) {
  EXPECT_EQ(WithMember("{}", "field", "[1]"), R"({"field":[1]})");
  EXPECT_EQ(WithMember(R"({"id":"x"})", "field", "{}"), R"({"id":"x","field":{}})");
  EXPECT_EQ(json::parse(WithMember(R"({"a":{"b":2}})", "c", "3")),
            json::parse(R"({"a":{"b":2},"c":3})"));
}

}  // namespace
}  // namespace surfdeform
