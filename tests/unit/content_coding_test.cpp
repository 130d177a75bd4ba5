// gzip for answers that compress (service/content_coding.hpp): who accepts
// it, and bytes that zlib inflates back.
#include "service/content_coding.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <string>

namespace surfdeform {
namespace {

std::string Inflate(const std::string& gz, size_t size) {
  z_stream z{};
  EXPECT_EQ(inflateInit2(&z, 15 + 32), Z_OK);
  std::string out(size + 16, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(gz.data()));
  z.avail_in = static_cast<uInt>(gz.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(inflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  inflateEnd(&z);
  return out;
}

TEST(ContentCoding, AcceptsGzipAsRfc9110Says) {
  EXPECT_TRUE(AcceptsGzip("gzip"));
  EXPECT_TRUE(AcceptsGzip("gzip, deflate, br"));
  EXPECT_TRUE(AcceptsGzip("deflate, gzip;q=0.5"));
  EXPECT_TRUE(AcceptsGzip("x-gzip"));
  EXPECT_TRUE(AcceptsGzip("*"));
  EXPECT_TRUE(AcceptsGzip("GZIP"));  // codings are case-insensitive
  EXPECT_FALSE(AcceptsGzip(""));
  EXPECT_FALSE(AcceptsGzip("identity"));
  EXPECT_FALSE(AcceptsGzip("deflate, br"));
  EXPECT_FALSE(AcceptsGzip("gzip;q=0"));
  EXPECT_FALSE(AcceptsGzip("gzip; q=0.000"));
  EXPECT_FALSE(AcceptsGzip("gzipped"));
}

TEST(ContentCoding, GzipInflatesBack) {
  std::string data;
  for (int k = 0; k < 20000; ++k) data += std::to_string(k % 97) + ",";
  const std::string gz = GzipFast(data);
  ASSERT_FALSE(gz.empty());
  EXPECT_LT(gz.size(), data.size() / 3);
  EXPECT_EQ(static_cast<unsigned char>(gz[0]), 0x1f);  // a gzip member
  EXPECT_EQ(static_cast<unsigned char>(gz[1]), 0x8b);
  EXPECT_EQ(Inflate(gz, data.size()), data);
  EXPECT_EQ(Inflate(GzipFast(""), 0), "");
}

// The types httplib 0.11.4 would gzip itself at its default level, which
// the HTTP layer gzips at level 1 instead; answers of other types are left
// to their own encodings.
TEST(ContentCoding, KnowsWhatHttplibWouldGzip) {
  EXPECT_TRUE(HttplibWouldGzip("application/json"));
  EXPECT_TRUE(HttplibWouldGzip("text/plain; version=0.0.4"));
  EXPECT_TRUE(HttplibWouldGzip("image/svg+xml"));
  EXPECT_FALSE(HttplibWouldGzip("text/event-stream"));
  EXPECT_FALSE(HttplibWouldGzip("application/problem+json"));
  EXPECT_FALSE(HttplibWouldGzip("model/gltf-binary"));
  EXPECT_FALSE(HttplibWouldGzip("application/octet-stream"));
}

}  // namespace
}  // namespace surfdeform
