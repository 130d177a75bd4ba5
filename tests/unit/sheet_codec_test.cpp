// The shared tier's value format: a round trip is exact, and every damaged,
// truncated or foreign value is refused.
#include "service/sheet_codec.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

FlatSheet SmallSheet() {
  auto surface = testing::MakeValid(WaveSpec{});
  SamplingOptions sampling;
  sampling.nu = 5;
  sampling.nv = 4;
  auto sheet = FlattenSurface(*surface, sampling);
  EXPECT_TRUE(sheet.ok());
  return sheet.ok() ? *sheet : FlatSheet{};
}

const EncodedSheetParts kParts = {
    R"({"sampling":{"nu":5,"nv":4},"surface":{"kind":"wave"}})", 12.5, {}, 0, 0};

TEST(SheetCodec, RoundTripIsExact) {
  const FlatSheet sheet = SmallSheet();
  ASSERT_EQ(sheet.points.size(), 20u);
  const std::string bytes = EncodeSheet(sheet, kParts);
  auto back = DecodeSheet(bytes, 256);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  const FlatSheet& b = back->sheet;
  EXPECT_EQ(b.nu, 5);
  EXPECT_EQ(b.nv, 4);
  EXPECT_EQ(b.points, sheet.points);
  EXPECT_EQ(b.normals, sheet.normals);
  EXPECT_EQ(b.flat, sheet.flat);
  EXPECT_EQ(b.method, sheet.method);
  EXPECT_EQ(b.frame_linear, sheet.frame_linear);
  EXPECT_EQ(b.frame_offset, sheet.frame_offset);
  EXPECT_EQ(b.quality.stress, sheet.quality.stress);
  EXPECT_EQ(b.quality.iterations, sheet.quality.iterations);
  EXPECT_EQ(b.quality.converged, sheet.quality.converged);
  EXPECT_EQ(back->parts.canonical_request, kParts.canonical_request);
  EXPECT_EQ(back->parts.flatten_ms, 12.5);
}

TEST(SheetCodec, AMeshSurfaceKeepsItsFlatVerticesWithinTheLimit) {
  const FlatSheet sheet = SmallSheet();
  EncodedSheetParts parts = kParts;
  parts.mesh_flat = {Vec2(0.5, -1.25), Vec2(3.0, 1e-300), Vec2(-7.0, 2.0)};
  parts.mesh_pairs = 11;
  parts.mesh_dropped_pairs = 2;
  const std::string bytes = EncodeSheet(sheet, parts);
  auto back = DecodeSheet(bytes, 256);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->parts.mesh_flat, parts.mesh_flat);
  EXPECT_EQ(back->parts.mesh_pairs, 11u);
  EXPECT_EQ(back->parts.mesh_dropped_pairs, 2u);
  EXPECT_EQ(back->sheet.flat, sheet.flat);
  // More flat vertices than the reader allows: refused before they are read.
  EXPECT_FALSE(DecodeSheet(bytes, 256, 2).ok());
  EXPECT_TRUE(DecodeSheet(bytes, 256, 3).ok());
  // A sheet without a mesh has none.
  auto plain = DecodeSheet(EncodeSheet(sheet, kParts), 256);
  ASSERT_TRUE(plain.ok());
  EXPECT_TRUE(plain->parts.mesh_flat.empty());
}

TEST(SheetCodec, APeriodicSheetKeepsItsPeriod) {
  auto surface = testing::MakeValid(SphereSpec{1.0, 0.0, 360.0, -30.0, 30.0, {}});
  auto sheet = FlattenSurface(*surface, {17, 5});
  ASSERT_TRUE(sheet.ok()) << sheet.status().ToString();
  ASSERT_FALSE(sheet->period_u.isZero());
  auto back = DecodeSheet(EncodeSheet(*sheet, kParts), 256);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->sheet.period_u, sheet->period_u);
  EXPECT_EQ(back->sheet.period_v, sheet->period_v);
  EXPECT_EQ(back->sheet.flat, sheet->flat);
}

TEST(SheetCodec, EveryFlippedByteAndEveryTruncationIsRefused) {
  const std::string bytes = EncodeSheet(SmallSheet(), kParts);
  for (size_t k = 0; k < bytes.size(); ++k) {
    std::string damaged = bytes;
    damaged[k] ^= 0x20;
    EXPECT_FALSE(DecodeSheet(damaged, 256).ok()) << "byte " << k;
  }
  for (size_t n = 0; n < bytes.size(); ++n) {
    EXPECT_FALSE(DecodeSheet(std::string_view(bytes).substr(0, n), 256).ok()) << n << " bytes";
  }
  EXPECT_FALSE(DecodeSheet(bytes + "x", 256).ok());
  EXPECT_FALSE(DecodeSheet("", 256).ok());
  EXPECT_FALSE(DecodeSheet(std::string(1000, '\0'), 256).ok());
}

TEST(SheetCodec, AGridLargerThanTheServersLimitIsRefused) {
  const std::string bytes = EncodeSheet(SmallSheet(), kParts);
  EXPECT_TRUE(DecodeSheet(bytes, 5).ok());
  auto refused = DecodeSheet(bytes, 4);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("grid size"), std::string::npos);
}

TEST(SheetCodec, KeysCarryTheFormatAndTheEngineVersion) {
  const std::string key = SheetKey("0123456789abcdef0123456789abcdef");
  EXPECT_EQ(key, "surfdeform:sheet:v" + std::to_string(kSheetFormatVersion) + ":" +
                     SURFDEFORM_VERSION + ":0123456789abcdef0123456789abcdef");
  EXPECT_EQ(SheetLockKey("ab"), SheetKey("ab") + ":lock");
}

}  // namespace
}  // namespace surfdeform
