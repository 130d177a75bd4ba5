// The server's log (http/log_writer.hpp): lines go out in order; when the
// reader stalls, writing never blocks and lines past the queue are dropped
// and counted.
#include "http/log_writer.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <string>
#include <thread>

namespace surfdeform::http {
namespace {

TEST(LogWriter, LinesGoOutInOrder) {
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  {
    LogWriter log(100, fds[1]);
    for (int k = 0; k < 50; ++k) log.Write("line " + std::to_string(k));
  }  // the writer drains before it ends
  close(fds[1]);
  std::string out;
  char buf[4096];
  ssize_t n;
  while ((n = read(fds[0], buf, sizeof buf)) > 0) out.append(buf, static_cast<size_t>(n));
  close(fds[0]);
  std::string expected;
  for (int k = 0; k < 50; ++k) expected += "line " + std::to_string(k) + "\n";
  EXPECT_EQ(out, expected);
}

TEST(LogWriter, AStalledReaderNeverBlocksAWriteAndLinesAreDroppedAndCounted) {
  // The writer's end may still be blocked when the reader's end closes:
  // its write() fails then (the server ignores SIGPIPE too).
  signal(SIGPIPE, SIG_IGN);
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  fcntl(fds[1], F_SETPIPE_SZ, 4096);
  const std::string line(200, 'x');
  const auto t0 = std::chrono::steady_clock::now();
  uint64_t dropped = 0;
  {
    LogWriter log(64, fds[1]);
    for (int k = 0; k < 5000; ++k) log.Write(line);  // far past the pipe and the queue
    dropped = log.dropped();
    EXPECT_GT(dropped, 4000u);
    EXPECT_LE(log.written(), 5000u - dropped);
  }
  // The writes never waited: the loop and the writer's end (a bounded wait
  // for the stalled reader) took no more than the writer's drain bound.
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
  close(fds[0]);
  close(fds[1]);
}

}  // namespace
}  // namespace surfdeform::http
