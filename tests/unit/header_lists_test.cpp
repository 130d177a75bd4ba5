// HTTP list headers (base/header_lists.hpp): elements, parameters, weights
// and whitespace as RFC 9110 section 5.6.1 and 12.4.2 spell them.
#include "base/header_lists.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace surfdeform {
namespace {

// "value|parameters|refused" for each non-empty element.
std::vector<std::string> Items(std::string_view header) {
  std::vector<std::string> out;
  AnyHeaderListItem(header, [&out](const HeaderListItem& item) {
    std::string row(item.value);
    row += '|';
    row += item.parameters;
    row += item.refused ? "|0" : "|1";
    out.push_back(row);
    return false;
  });
  return out;
}

TEST(HeaderLists, SplitsTrimsAndSkipsEmptyElements) {
  EXPECT_EQ(Items(""), std::vector<std::string>{});
  EXPECT_EQ(Items(" , ,\t"), std::vector<std::string>{});
  EXPECT_EQ(Items("a,b"), (std::vector<std::string>{"a||1", "b||1"}));
  EXPECT_EQ(Items(" text/html ;\tlevel=1 , ,*/*"),
            (std::vector<std::string>{"text/html|level=1|1", "*/*||1"}));
}

TEST(HeaderLists, OnlyAZeroWeightRefuses) {
  EXPECT_EQ(Items("gzip;q=0"), std::vector<std::string>{"gzip|q=0|0"});
  EXPECT_EQ(Items("gzip; Q = 0.000"), std::vector<std::string>{"gzip|Q = 0.000|0"});
  EXPECT_EQ(Items("a;level=1;q=0."), std::vector<std::string>{"a|level=1;q=0.|0"});
  EXPECT_EQ(Items("gzip;q=0.001"), std::vector<std::string>{"gzip|q=0.001|1"});
  EXPECT_EQ(Items("gzip;q=1"), std::vector<std::string>{"gzip|q=1|1"});
  EXPECT_EQ(Items("gzip;q="), std::vector<std::string>{"gzip|q=|1"});
  EXPECT_EQ(Items("gzip;level=0"), std::vector<std::string>{"gzip|level=0|1"});
}

TEST(HeaderLists, StopsAtTheFirstElementTheCallerTakes) {
  int seen = 0;
  EXPECT_TRUE(AnyHeaderListItem("a, b, c", [&seen](const HeaderListItem& item) {
    ++seen;
    return item.value == "b";
  }));
  EXPECT_EQ(seen, 2);
  EXPECT_FALSE(AnyHeaderListItem("a, b", [](const HeaderListItem&) { return false; }));
}

TEST(HeaderLists, TrimsOnlySpacesAndTabsAndComparesWithoutCase) {
  EXPECT_EQ(TrimHttpSpace(" \t x y\t "), "x y");
  EXPECT_EQ(TrimHttpSpace("\r\nx"), "\r\nx");
  EXPECT_TRUE(EqualsIgnoringCase("Model/GLTF-Binary", "model/gltf-binary"));
  EXPECT_FALSE(EqualsIgnoringCase("gzip", "gzip2"));
  EXPECT_FALSE(EqualsIgnoringCase("gzip", "gzap"));
}

}  // namespace
}  // namespace surfdeform
