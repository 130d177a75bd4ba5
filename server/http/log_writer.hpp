// The server's log lines (JSON, one a line) go to standard output through a
// bounded queue and a thread of their own: a request never waits for the
// log's reader. When the reader stalls and the queue is full, lines are
// dropped and counted (docs/RELIABILITY.md, item 36).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <thread>

namespace surfdeform::http {

class LogWriter {
 public:
  // Lines go to `fd` (standard output by default).
  explicit LogWriter(size_t max_queued_lines = 8192, int fd = 1);
  // Writes what is queued, waiting at most a second for a stalled reader.
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  // Queues `line` (a newline is added); never blocks.
  void Write(std::string line);
  uint64_t dropped() const;
  uint64_t written() const;  // lines

 private:
  struct Queue;  // shared with the writing thread, which may outlive this
  std::shared_ptr<Queue> queue_;
  std::thread thread_;
};

}  // namespace surfdeform::http
