// One table per enum: every value has one name, every name one value, and
// parsing and printing go through the table.
#include <gtest/gtest.h>

#include <set>

#include "engine/flatten/flatten.hpp"
#include "engine/placement/placement.hpp"
#include "engine/subdivision/subdivide.hpp"
#include "proto/api.hpp"
#include "proto/json_object.hpp"

namespace surfdeform {
namespace {

// Names unique and non-empty, a description for each, and every value from
// 0 to count - 1 present once, round-tripping through the name.
template <typename E>
void ExpectComplete(std::span<const EnumEntry<E>> table, int count) {
  std::set<std::string_view> names;
  std::set<int> values;
  for (const EnumEntry<E>& e : table) {
    EXPECT_FALSE(e.name.empty());
    EXPECT_FALSE(e.description.empty()) << e.name;
    EXPECT_TRUE(names.insert(e.name).second) << "repeated name " << e.name;
    EXPECT_TRUE(values.insert(static_cast<int>(e.value)).second) << e.name;
    EXPECT_EQ(ValueOf(table, e.name), e.value) << e.name;
    EXPECT_EQ(NameOf(table, e.value), e.name);
  }
  EXPECT_EQ(static_cast<int>(values.size()), count);
  for (int v = 0; v < count; ++v) EXPECT_EQ(values.count(v), 1u) << v;
  EXPECT_EQ(ValueOf(table, "no such name"), std::nullopt);
}

TEST(EnumTables, EveryTableNamesEachValueOnce) {
  ExpectComplete<FlattenMethod>(kFlattenMethods, 2);
  ExpectComplete<UpAxis>(kUpAxes, 7);
  ExpectComplete<AnchorMode>(kAnchorModes, 3);  // kValue is a number, not a name
  ExpectComplete<OutsideMode>(kOutsideModes, 3);
  ExpectComplete<SubdivisionMode>(kSubdivisionModes, 3);
  ExpectComplete<proto::OutputFormat>(proto::kOutputFormats, 7);
  ExpectComplete<BodySide>(kBodySides, 3);
  ExpectComplete<proto::SurfaceKind>(proto::kSurfaceKinds, 10);
  ExpectComplete<ErrorCode>(kErrorCodes, static_cast<int>(ErrorCode::kUnavailable) + 1);
}

TEST(EnumTables, TheNameFunctionsReadTheTables) {
  for (const auto& e : kSubdivisionModes) EXPECT_EQ(SubdivisionModeName(e.value), e.name);
  for (const auto& e : kFlattenMethods) EXPECT_EQ(FlattenMethodName(e.value), e.name);
  for (const auto& e : proto::kOutputFormats) EXPECT_EQ(proto::OutputFormatName(e.value), e.name);
  for (const auto& e : kErrorCodes) EXPECT_EQ(ErrorCodeName(e.value), e.name);
}

// The engine's KindOf (animation keys) names each spec as the API writes it
// (the canonical JSON's "kind"), and every kind of the table is met.
TEST(EnumTables, KindOfNamesEachSpecAsTheApiDoes) {
  BSplineSpec rational;
  rational.rational = true;
  const SurfaceSpec specs[] = {BezierSpec{}, BSplineSpec{}, rational,   CylinderSpec{}, ConeSpec{},
                               SphereSpec{}, TorusSpec{},   WaveSpec{}, GridSpec{},     MeshSpec{}};
  std::set<SurfaceKind> seen;
  for (const SurfaceSpec& spec : specs) {
    proto::SurfaceRequest request;
    request.surface = spec;
    const std::string api = proto::CanonicalJson(request)["surface"]["kind"];
    EXPECT_EQ(KindName(KindOf(spec)), api);
    seen.insert(KindOf(spec));
  }
  EXPECT_EQ(seen.size(), std::size(proto::kSurfaceKinds));
}

TEST(EnumTables, ChoiceParsesByTheTableAndListsItsNamesOnError) {
  const nlohmann::json j = {{"up", "-y"}, {"bad", "sideways"}};
  auto o = proto::JsonObject::Open(j, "placement");
  ASSERT_TRUE(o.ok());
  UpAxis up = UpAxis::kPosZ;
  ASSERT_TRUE(o->Choice<UpAxis>("up", kUpAxes, &up).ok());
  EXPECT_EQ(up, UpAxis::kNegY);
  UpAxis untouched = UpAxis::kPosZ;
  ASSERT_TRUE(o->Choice<UpAxis>("absent", kUpAxes, &untouched).ok());
  EXPECT_EQ(untouched, UpAxis::kPosZ);
  const Status bad = o->Choice<UpAxis>("bad", kUpAxes, &up);
  EXPECT_EQ(bad.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(bad.field(), "placement.bad");
  for (const auto& e : kUpAxes) EXPECT_NE(bad.message().find(e.name), std::string::npos);
}

}  // namespace
}  // namespace surfdeform
