// Memory under hostile input, measured on the real server process
// (docs/RELIABILITY.md, items 1, 5, 7 and 15): headers that claim counts the
// body cannot hold, chunked and oversized bodies, huge header lines. Each is
// refused, and the process's peak resident set (VmHWM) does not grow by
// anything like what the claims would have cost.
#include <gtest/gtest.h>
#include <httplib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>

#include "server_process.hpp"

namespace surfdeform::testing {
namespace {

using namespace std::chrono_literals;

// A field of /proc/PID/status, in kB (VmHWM: the peak resident set).
long StatusKb(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  }
  return -1;
}

std::string Varint(uint64_t v) {
  std::string out;
  do {
    uint8_t b = v & 0x7f;
    v >>= 7;
    if (v != 0) b |= 0x80;
    out += static_cast<char>(b);
  } while (v != 0);
  return out;
}

// Sends `bytes` and waits for the status line (or the server closing).
std::string StatusLine(int port, const std::string& bytes) {
  const int fd = ConnectLoopback(port);
  if (fd < 0) return "";
  timeval tv{10, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  SendAll(fd, bytes);  // the server may refuse before it has all of it
  std::string reply;
  char buf[4096];
  while (reply.find("\r\n") == std::string::npos) {
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    reply.append(buf, static_cast<size_t>(n));
  }
  close(fd);
  return reply.substr(0, reply.find("\r\n"));
}

const char kParams[] = R"({"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180}})";

std::string RawDeform(const std::string& mesh) {
  return std::string("POST /v1/deform HTTP/1.1\r\nHost: x\r\nX-Surfdeform-Params: ") + kParams +
         "\r\nContent-Type: application/octet-stream\r\nContent-Length: " +
         std::to_string(mesh.size()) + "\r\n\r\n" + mesh;
}

TEST(BoundedMemory, ClaimsTheBodyCannotHoldCostNoMemory) {
  ServerProcess server({"--log-level", "error"});  // the published default limits
  ASSERT_GT(server.port(), 0);
  const int port = server.port();
  // Warm: one real deformation, so that what stays allocated is allocated.
  httplib::Client c("127.0.0.1", port);
  const std::string plate = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  auto warm =
      c.Post("/v1/deform", {{"X-Surfdeform-Params", kParams}}, plate, "application/octet-stream");
  ASSERT_TRUE(warm);
  ASSERT_EQ(warm->status, 200) << warm->body;
  const long before = StatusKb(server.pid(), "VmHWM");
  ASSERT_GT(before, 0);

  // Item 7 and 15: a 19-byte sequential .drc that claims 1.9 million
  // vertices and 3.9 million triangles, under the published limits (2M, 4M):
  // Draco would size its buffers from them (about 100 MB).
  const std::string drc = std::string("DRACO\x02\x02\x01\x00\x00\x00", 11) + Varint(3'900'000) +
                          Varint(1'900'000) + std::string(4, '\0');
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(StatusLine(port, RawDeform(drc)).substr(9, 3), "413") << "the .drc claim";
  }
  // A binary PLY that claims 1.9 million vertices and 3.9 million faces in
  // a few bytes of body.
  const std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1900000\nproperty float x\nproperty "
      "float y\nproperty float z\nelement face 3900000\nproperty list uchar int vertex_indices\n"
      "end_header\n" +
      std::string(64, '\0');
  for (int k = 0; k < 5; ++k) {
    const std::string status = StatusLine(port, RawDeform(ply));
    EXPECT_TRUE(status.substr(9, 3) == "422" || status.substr(9, 3) == "413") << status;
  }
  // Item 1: a chunked body of 50 MB (the limit is 64 MiB): refused, not read.
  std::string chunked =
      "POST /v1/surfaces HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
      "Transfer-Encoding: chunked\r\n\r\n";
  const std::string chunk(1 << 20, ' ');
  char size_line[32];
  std::snprintf(size_line, sizeof size_line, "%zx\r\n", chunk.size());
  for (int k = 0; k < 50; ++k) chunked += size_line + chunk + "\r\n";
  chunked += "0\r\n\r\n";
  EXPECT_EQ(StatusLine(port, chunked).substr(9, 3), "411");
  // Item 5: a 1 MB header line and 10,000 headers.
  EXPECT_EQ(StatusLine(port, "GET /healthz HTTP/1.1\r\nHost: x\r\nX-Big: " +
                                 std::string(1 << 20, 'a') + "\r\n\r\n")
                .substr(9, 3),
            "431");
  std::string many = "GET /healthz HTTP/1.1\r\nHost: x\r\n";
  for (int k = 0; k < 10000; ++k) many += "X-H" + std::to_string(k) + ": 1\r\n";
  EXPECT_EQ(StatusLine(port, many + "\r\n").substr(9, 3), "431");

  std::this_thread::sleep_for(200ms);
  const long after = StatusKb(server.pid(), "VmHWM");
  // What the claims would have cost is hundreds of MB; a few MB of slack
  // for the buffers of the requests themselves.
  EXPECT_LT(after - before, 16 * 1024)
      << "peak RSS grew from " << before << " kB to " << after << " kB";
  auto health = c.Get("/healthz");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
}

}  // namespace
}  // namespace surfdeform::testing
