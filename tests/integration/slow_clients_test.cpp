// Slow clients against the real server, with no proxy in front
// (docs/RELIABILITY.md, items 8 and 30): heads trickled a line at a time,
// bodies trickled a few bytes at a time, idle keep-alive connections, and
// readers of large responses that read a few bytes at a time, each on twice
// the worker count. The server closes them by its own deadlines, and
// /healthz and a real request keep answering meanwhile.
#include <gtest/gtest.h>
#include <httplib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "server_process.hpp"
#include "shared_server.hpp"

namespace surfdeform::testing {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr int kWorkers = 4;
constexpr auto kHeadTimeout = 1500ms;

// A slow client: sends `first`, then `piece` every `every` until the server
// closes the connection (or `give_up`). Records what the server sent and
// when it closed.
struct SlowClient {
  std::string received;
  Clock::duration closed_after{};
  bool closed = false;
};

void Trickle(int port, const std::string& first, const std::string& piece,
             std::chrono::milliseconds every, std::chrono::milliseconds give_up, SlowClient* out) {
  const auto start = Clock::now();
  const int fd = ConnectLoopback(port);
  if (fd < 0) return;
  timeval tv{0, 1000 * static_cast<suseconds_t>(every.count())};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  bool sending = SendAll(fd, first);
  char buf[4096];
  while (Clock::now() - start < give_up) {
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
      out->closed = true;
      out->closed_after = Clock::now() - start;
      break;
    }
    if (n > 0) out->received.append(buf, static_cast<size_t>(n));
    if (sending) sending = SendAll(fd, piece);
  }
  close(fd);
}

// A slow reader: a receive buffer of 4 KB (set before connecting, so the
// window stays small), `request` sent at once, then `piece` bytes read every
// `every` until the server closes the connection (or `give_up`).
void SlowRead(int port, const std::string& request, size_t piece, std::chrono::milliseconds every,
              std::chrono::milliseconds give_up, SlowClient* out) {
  const auto start = Clock::now();
  const int fd = ConnectLoopback(port, 4096);
  if (fd < 0) return;
  if (!SendAll(fd, request)) {
    close(fd);
    return;
  }
  std::vector<char> buf(piece);
  while (Clock::now() - start < give_up) {
    std::this_thread::sleep_for(every);
    const ssize_t n = recv(fd, buf.data(), buf.size(), MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
      out->closed = true;
      out->closed_after = Clock::now() - start;
      break;
    }
    if (n > 0) out->received.append(buf.data(), static_cast<size_t>(n));
  }
  close(fd);
}

// `count` slow clients at once, each running `client` (Trickle or SlowRead).
struct SlowCrowd {
  std::vector<SlowClient> clients;
  std::vector<std::thread> threads;
  template <typename Client, typename... Args>
  SlowCrowd(int count, Client client, const Args&... args) : clients(static_cast<size_t>(count)) {
    for (SlowClient& c : clients) threads.emplace_back(client, args..., &c);
    std::this_thread::sleep_for(300ms);  // every slow connection is open
  }
  const std::vector<SlowClient>& Join() {
    for (auto& t : threads) t.join();
    return clients;
  }
};

// While slow connections run, /healthz and a real request must each answer
// within `bound`, several times over.
void ExpectServingOn(int port, std::chrono::milliseconds bound) {
  for (int round = 0; round < 4; ++round) {
    httplib::Client c("127.0.0.1", port);
    c.set_connection_timeout(5, 0);
    c.set_read_timeout(5, 0);
    auto t0 = Clock::now();
    auto health = c.Get("/healthz");
    EXPECT_TRUE(health && health->status == 200) << "round " << round;
    EXPECT_LT(Clock::now() - t0, bound) << "/healthz, round " << round;
    t0 = Clock::now();
    auto created = c.Post("/v1/surfaces",
                          R"({"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":)" +
                              std::to_string(60 + round) + R"(},"sampling":{"nu":8,"nv":8}})",
                          "application/json");
    EXPECT_TRUE(created && (created->status == 201 || created->status == 200)) << "round " << round;
    EXPECT_LT(Clock::now() - t0, bound) << "POST /v1/surfaces, round " << round;
    std::this_thread::sleep_for(200ms);
  }
}

// A counter of /metrics: surfdeform_connections_closed_total{reason=...}.
double ClosedConnections(int port, const std::string& reason) {
  return ScrapeMetric(port, "surfdeform_connections_closed_total{reason=\"" + reason + "\"}");
}

class SlowClients : public SharedServerTest<SlowClients> {
 public:
  static std::vector<std::string> Args() {
    return {"--log-level",          "error",
            "--http-threads",       std::to_string(kWorkers),
            "--head-timeout-ms",    std::to_string(kHeadTimeout.count()),
            "--transfer-grace",     "1",
            "--min-transfer-rate",  "65536",
            "--keep-alive-timeout", "3"};
  }

 protected:
  void ExpectServing(std::chrono::milliseconds bound) { ExpectServingOn(port(), bound); }
  double Closed(const std::string& reason) { return ClosedConnections(port(), reason); }
};

TEST_F(SlowClients, TrickledHeadsNeverHoldAWorkerAndGet408) {
  const double before = Closed("head_timeout");
  constexpr int kCount = 2 * kWorkers * 4;  // well past twice the workers
  SlowCrowd crowd(kCount, Trickle, port(), "GET /healthz HTTP/1.1\r\nHost: x\r\n", "X-Slow: 1\r\n",
                  200ms, 10000ms);
  ExpectServing(1000ms);
  for (const SlowClient& c : crowd.Join()) {
    EXPECT_TRUE(c.closed) << "a trickling head was never cut off";
    EXPECT_LT(c.closed_after, kHeadTimeout + 1000ms);
    EXPECT_EQ(c.received.rfind("HTTP/1.1 408", 0), 0u) << c.received.substr(0, 80);
    EXPECT_NE(c.received.find("application/problem+json"), std::string::npos);
  }
  EXPECT_GE(Closed("head_timeout") - before, kCount);
}

// A body is read by the gate, off the workers, and must keep pace with the
// minimum rate past the grace: trickled from the start, it is cut soon after
// the grace (408), and twice the workers of them never stop the service.
TEST_F(SlowClients, BodiesTrickledFromTheStartNeverHoldAWorkerAndGet408) {
  const double before = Closed("slow_body");
  constexpr int kCount = 2 * kWorkers;  // the most one address may send at once (8)
  const std::string head =
      "POST /v1/surfaces HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
      "Content-Length: 1000000\r\n\r\n";
  SlowCrowd crowd(kCount, Trickle, port(), head + "{", "  ", 100ms, 10000ms);
  ExpectServing(1000ms);
  for (const SlowClient& c : crowd.Join()) {
    EXPECT_TRUE(c.closed);
    EXPECT_LT(c.closed_after, 1000ms + 1500ms);  // the grace, and the gate's tick
    EXPECT_EQ(c.received.rfind("HTTP/1.1 408", 0), 0u) << c.received.substr(0, 80);
  }
  EXPECT_GE(Closed("slow_body") - before, kCount);
}

// A body that starts fast and then slows down is cut once its pace falls
// under the minimum rate: 20 KiB at once, then 100 bytes a tick, under
// 64 KiB/s past the 1 s grace at about 1.3 s.
TEST_F(SlowClients, BodiesThatSlowDownAreCutOffAtTheMinimumRate) {
  const double before = Closed("slow_body");
  constexpr int kCount = 2 * kWorkers;
  const std::string head =
      "POST /v1/deform HTTP/1.1\r\nHost: x\r\nContent-Type: application/octet-stream\r\n"
      "Content-Length: 1000000\r\n\r\n";
  SlowCrowd crowd(kCount, Trickle, port(), head + std::string(20 * 1024, 'x'),
                  std::string(100, 'x'), 100ms, 15000ms);
  ExpectServing(1000ms);
  for (const SlowClient& c : crowd.Join()) {
    EXPECT_TRUE(c.closed) << "a trickling body was never cut off";
    EXPECT_LT(c.closed_after, 3000ms);
    EXPECT_EQ(c.received.rfind("HTTP/1.1 408", 0), 0u) << c.received.substr(0, 80);
  }
  EXPECT_GE(Closed("slow_body") - before, kCount);
}

// Past the bodies one address may send at once, the next is refused at
// once (503 with Retry-After) before a byte of it is read.
TEST_F(SlowClients, BodiesPastThePerAddressLimitAre503) {
  const double before = Closed("bodies_refused");
  const std::string head =
      "POST /v1/surfaces HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
      "Content-Length: 1000000\r\n\r\n";
  SlowCrowd crowd(8 + 3, Trickle, port(), head + "{", "  ", 100ms, 5000ms);
  int refused = 0;
  for (const SlowClient& c : crowd.Join()) {
    if (c.received.rfind("HTTP/1.1 503", 0) != 0) continue;
    ++refused;
    EXPECT_NE(c.received.find("Retry-After:"), std::string::npos);
    EXPECT_LT(c.closed_after, 1000ms);
  }
  EXPECT_EQ(refused, 3);
  EXPECT_EQ(Closed("bodies_refused") - before, 3);
}

TEST_F(SlowClients, IdleKeepAliveConnectionsWaitOffTheWorkers) {
  // Three times the workers, each kept alive after one request (the
  // keep-alive timeout is 3 s): none may hold a worker while it idles.
  std::vector<std::unique_ptr<httplib::Client>> idle;
  for (int k = 0; k < 3 * kWorkers; ++k) {
    idle.push_back(std::make_unique<httplib::Client>("127.0.0.1", port()));
    idle.back()->set_keep_alive(true);
    auto r = idle.back()->Get("/v1/info");
    ASSERT_TRUE(r && r->status == 200);
  }
  ExpectServing(1000ms);
  // And they are still usable: their next request is served.
  for (auto& c : idle) {
    auto r = c->Get("/v1/info");
    EXPECT_TRUE(r && r->status == 200);
  }
}

TEST_F(SlowClients, AKeptAliveConnectionThatTricklesItsNextHeadIsClosed) {
  const int fd = ConnectLoopback(port());
  ASSERT_GE(fd, 0);
  // (Not a probe: /healthz is served one request to a connection.)
  ASSERT_TRUE(SendAll(fd, "GET /v1/info HTTP/1.1\r\nHost: x\r\n\r\n"));
  char buf[4096];
  // The first answer whole: its head, then Content-Length bytes of body.
  std::string first;
  size_t whole = std::string::npos;
  while (whole == std::string::npos || first.size() < whole) {
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    ASSERT_GT(n, 0);
    first.append(buf, static_cast<size_t>(n));
    const size_t head_end = first.find("\r\n\r\n");
    const size_t length_at = first.find("Content-Length: ");
    if (whole == std::string::npos && head_end != std::string::npos &&
        length_at != std::string::npos && length_at < head_end) {
      whole = head_end + 4 + std::stoul(first.substr(length_at + 16));
    }
  }
  ASSERT_EQ(first.size(), whole);
  const auto start = Clock::now();
  ASSERT_TRUE(SendAll(fd, "GET /v1/info HTTP/1.1\r\n"));
  timeval tv{0, 200000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  std::string received;
  bool closed = false;
  while (Clock::now() - start < 15s) {
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n == 0) {
      closed = true;
      break;
    }
    if (n > 0) received.append(buf, static_cast<size_t>(n));
    SendAll(fd, "X-Slow: 1\r\n");
  }
  close(fd);
  EXPECT_TRUE(closed);
  // Its budget: the keep-alive wait plus the head timeout.
  EXPECT_LT(Clock::now() - start, 3s + kHeadTimeout + 1500ms);
  EXPECT_EQ(received.rfind("HTTP/1.1 408", 0), 0u) << received.substr(0, 80);
}

// A flood of silent connections past the gate's 512 places
// cannot keep a liveness probe out. The longest waiting are closed to make
// room; /healthz answers 200 (not 503) at once, and so does a real request.
TEST_F(SlowClients, LivenessAnswersThroughAFloodOfSilentConnections) {
  const double before = Closed("evicted");
  std::vector<int> silent;
  for (int k = 0; k < 600; ++k) {
    const int fd = ConnectLoopback(port());
    if (fd >= 0) silent.push_back(fd);
  }
  ASSERT_GE(silent.size(), 590u);
  std::this_thread::sleep_for(200ms);  // the gate has them all
  for (int k = 0; k < 5; ++k) {
    httplib::Client c("127.0.0.1", port());
    c.set_connection_timeout(2, 0);
    c.set_read_timeout(2, 0);
    const auto t0 = Clock::now();
    auto r = c.Get("/healthz");
    ASSERT_TRUE(r) << "probe " << k << ": " << httplib::to_string(r.error());
    EXPECT_EQ(r->status, 200) << r->body;
    EXPECT_LT(Clock::now() - t0, 1s);
  }
  // At least the connections past the gate's places were closed to make room.
  EXPECT_GE(Closed("evicted") - before, 600.0 + 5 - 512 - 64);
  for (int fd : silent) close(fd);
}

// Slow readers: twice the workers each ask for a response larger than the
// kernel buffers between them and the server (the 1.4 MB sample; the
// server's send buffer at 64 KB, the client's receive window at 4 KB), then
// read 1 KB every 100 ms. What the socket does not take at once is sent by
// the gate, off the workers: the service answers at once meanwhile, and the
// gate cuts each reader once its response is due at the minimum rate
// (1 MiB/s past a 1 s grace here: about 2.4 s).
TEST(SlowReaders, ResponsesReadSlowerThanTheMinimumRateHoldNoWorkerAndAreCutOff) {
  ServerProcess server({"--log-level", "error", "--http-threads", std::to_string(kWorkers),
                        "--transfer-grace", "1", "--min-transfer-rate", "1048576", "--send-buffer",
                        "65536"});
  ASSERT_GT(server.port(), 0) << "the server did not start";
  const int port = server.port();
  httplib::Client c("127.0.0.1", port);
  auto sample = c.Get("/samples/bunny.ply");
  ASSERT_TRUE(sample && sample->status == 200);
  const size_t size = sample->body.size();
  ASSERT_GT(size, 1000000u);
  const auto due = 1000ms + std::chrono::milliseconds(size * 1000 / 1048576);

  const double before = ClosedConnections(port, "slow_response");
  constexpr int kCount = 2 * kWorkers;
  SlowCrowd crowd(kCount, SlowRead, port, "GET /samples/bunny.ply HTTP/1.1\r\nHost: x\r\n\r\n",
                  size_t{1024}, 100ms, 20000ms);
  ExpectServingOn(port, 1000ms);
  for (const SlowClient& r : crowd.Join()) {
    EXPECT_EQ(r.received.rfind("HTTP/1.1 200", 0), 0u) << r.received.substr(0, 80);
    EXPECT_TRUE(r.closed) << "a slow reader was never cut off";
    EXPECT_LT(r.received.size(), size) << "a slow reader got the whole response";
    EXPECT_LT(r.closed_after, due + 2000ms);
  }
  EXPECT_GE(ClosedConnections(port, "slow_response") - before, kCount);
  EXPECT_GE(ScrapeMetric(port, "surfdeform_gate_handled_total{kind=\"responses_kept\"}"), kCount);
}

}  // namespace
}  // namespace surfdeform::testing
