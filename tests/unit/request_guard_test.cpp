// The HTTP edge's checks on a request head before httplib parses it
// (http/request_guard.hpp): what cannot be framed is refused at once, with
// the status RFC 9112 and the published limits call for.
#include "http/request_guard.hpp"

#include <gtest/gtest.h>

#include <string>

namespace surfdeform::http {
namespace {

// The status CheckHead gives a complete head (0: accepted).
int StatusOfHead(const std::string& head) {
  const size_t end = head.find("\r\n\r\n");
  const auto r = CheckHead(head, end == std::string::npos ? kHeadIncomplete : end + 4);
  return r ? r->http_status : 0;
}

std::string WithHeaders(int count) {
  std::string head = "GET /healthz HTTP/1.1\r\n";
  for (int k = 0; k < count; ++k) head += "X-Field-" + std::to_string(k) + ": v\r\n";
  return head + "\r\n";
}

TEST(RequestGuard, WellFormedHeadsPass) {
  EXPECT_EQ(StatusOfHead("GET /healthz HTTP/1.1\r\nHost: a\r\n\r\n"), 0);
  EXPECT_EQ(StatusOfHead("GET / HTTP/1.0\r\n\r\n"), 0);
  EXPECT_EQ(StatusOfHead("POST /v1/deform?params=%7B%7D HTTP/1.1\r\nContent-Length: 3\r\n\r\nabc"),
            0);
  EXPECT_EQ(StatusOfHead("GET http://example.org:8080/healthz HTTP/1.1\r\n\r\n"), 0);
  EXPECT_EQ(StatusOfHead("OPTIONS * HTTP/1.1\r\n\r\n"), 0);
  EXPECT_EQ(StatusOfHead("GET / HTTP/1.1\r\nX-Empty:\r\nX-Tab:\tv\r\n\r\n"), 0);
  // A head still arriving is not judged by what has not come.
  EXPECT_FALSE(CheckHead("GET /healthz HTTP/1.1\r\nHost: a", kHeadIncomplete));
  EXPECT_FALSE(CheckHead("GE", kHeadIncomplete));
}

TEST(RequestGuard, RequestLinesThatCannotBeFramedAre400) {
  for (const char* head :
       {"XYZ / HTTP/1.1\r\n\r\n", "get / HTTP/1.1\r\n\r\n", "GET  / HTTP/1.1\r\n\r\n",
        "GET / HTTP/2.0\r\n\r\n", "GET /\r\n\r\n", "GET / HTTP/1.1 extra\r\n\r\n",
        "GET healthz HTTP/1.1\r\n\r\n", "GET ftp://host/x HTTP/1.1\r\n\r\n",
        "GET /a\x01 HTTP/1.1\r\n\r\n", "PRI * HTTP/2.0\r\n\r\n"}) {
    SCOPED_TRACE(head);
    EXPECT_EQ(StatusOfHead(head), 400);
  }
  const auto r = CheckHead("XYZ / HTTP/1.1\r\n\r\n", 18);
  ASSERT_TRUE(r);
  EXPECT_NE(r->status.message().find("unknown method"), std::string::npos) << r->status.message();
  // Refused as soon as the request line is in, before the rest of the head.
  EXPECT_TRUE(CheckHead("XYZ / HTTP/1.1\r\nHost: a", kHeadIncomplete));
}

TEST(RequestGuard, BareLineFeedsAreRefusedAtOnce) {
  EXPECT_EQ(StatusOfHead("GET / HTTP/1.1\nHost: a\n\n"), 400);
  // No blank CRLF line will ever come: refused on the first bare LF.
  const auto r = CheckHead("GET / HTTP/1.1\nHost: a\n", kHeadIncomplete);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->http_status, 400);
  EXPECT_NE(r->status.message().find("bare LF"), std::string::npos);
  EXPECT_TRUE(CheckHead("GET / HTTP/1.1\r\nHost: a\n", kHeadIncomplete));
}

TEST(RequestGuard, HeaderLinesMustBeNameColonValue) {
  EXPECT_EQ(StatusOfHead("GET / HTTP/1.1\r\nNo colon here\r\n\r\n"), 400);
  EXPECT_EQ(StatusOfHead("GET / HTTP/1.1\r\nName : v\r\n\r\n"), 400);
  EXPECT_EQ(StatusOfHead("GET / HTTP/1.1\r\n: v\r\n\r\n"), 400);
  EXPECT_EQ(StatusOfHead("GET / HTTP/1.1\r\nA: b\r\n folded\r\n\r\n"), 400);
  EXPECT_EQ(StatusOfHead("GET / HTTP/1.1\r\nA: b\x01\r\n\r\n"), 400);
}

TEST(RequestGuard, LongLinesAreRefusedWithTheLimitAndTheirLength) {
  const std::string target = "/v1/deform?params=" + std::string(9000, 'a');
  const std::string line = "POST " + target + " HTTP/1.1";
  const auto r = CheckHead(line + "\r\n\r\n", line.size() + 4);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->http_status, 414);
  ASSERT_TRUE(r->status.has_limit());
  EXPECT_EQ(r->status.limit(), kMaxRequestLineBytes);
  EXPECT_EQ(r->status.actual(), static_cast<double>(line.size()));
  // Refused before the line ends.
  EXPECT_TRUE(CheckHead(line.substr(0, 8200), kHeadIncomplete));
  EXPECT_FALSE(CheckHead(line.substr(0, 8100), kHeadIncomplete));
  // Exactly at the limit passes.
  const std::string longest =
      "GET /" + std::string(kMaxRequestLineBytes - 4 - 1 - 9, 'a') + " HTTP/1.1";
  ASSERT_EQ(longest.size(), kMaxRequestLineBytes);
  EXPECT_EQ(StatusOfHead(longest + "\r\n\r\n"), 0);
  EXPECT_EQ(
      StatusOfHead("GET /" + std::string(kMaxRequestLineBytes - 4 - 9, 'a') + " HTTP/1.1\r\n\r\n"),
      414);

  const std::string params = "X-Surfdeform-Params: " + std::string(8500, 'p');
  const auto h = CheckHead("POST /v1/deform HTTP/1.1\r\n" + params + "\r\n\r\n", kHeadIncomplete);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->http_status, 431);
  EXPECT_EQ(h->status.field(), "X-Surfdeform-Params");
  EXPECT_EQ(h->status.limit(), kMaxHeaderLineBytes);
  EXPECT_EQ(h->status.actual(), static_cast<double>(params.size()));
}

TEST(RequestGuard, HeaderFieldsAreCountedAsTheClientSentThem) {
  EXPECT_EQ(StatusOfHead(WithHeaders(97)), 0);
  EXPECT_EQ(StatusOfHead(WithHeaders(100)), 0);
  const std::string over = WithHeaders(101);
  const auto r = CheckHead(over, over.size());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->http_status, 431);
  EXPECT_EQ(r->status.actual(), 101);
  EXPECT_EQ(r->status.limit(), kMaxHeaderCount);
}

// httplib 0.11.4 does not read a body on GET, HEAD, OPTIONS or TRACE: one
// declared there is refused (and the connection ended), or it would be read
// as the next request (CL.0 smuggling behind a proxy's keep-alive).
TEST(RequestGuard, ABodyOnAMethodThatTakesNoneIs400) {
  for (const char* method : {"GET", "HEAD", "OPTIONS", "TRACE"}) {
    httplib::Request req;
    req.method = method;
    req.headers.emplace("Content-Length", "53");
    size_t length = 0;
    const auto r = CheckFraming(req, 1000, &length);
    ASSERT_TRUE(r) << method;
    EXPECT_EQ(r->http_status, 400) << method;
    EXPECT_EQ(r->status.field(), "Content-Length");
    req.headers.clear();
    req.headers.emplace("Content-Length", "0");
    EXPECT_FALSE(CheckFraming(req, 1000, &length)) << method;
  }
  httplib::Request post;
  post.method = "POST";
  post.headers.emplace("Content-Length", "53");
  size_t length = 0;
  EXPECT_FALSE(CheckFraming(post, 1000, &length));
  EXPECT_EQ(length, 53u);
}

TEST(RequestGuard, AControlCharacterInTheDecodedPathIs400) {
  EXPECT_FALSE(CheckPath("/index.html"));
  EXPECT_FALSE(CheckPath("/samples/a b.json"));
  const auto nul = CheckPath(std::string("/index.html\0.js", 15));
  ASSERT_TRUE(nul);
  EXPECT_EQ(nul->http_status, 400);
  EXPECT_EQ(nul->status.field(), "path");
  EXPECT_TRUE(CheckPath("/a\nb"));
  EXPECT_TRUE(CheckPath("/a\x7f"));
}

}  // namespace
}  // namespace surfdeform::http
