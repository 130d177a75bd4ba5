#include "http/log_writer.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>

namespace surfdeform::http {
namespace {

// The longest the server's end waits for a stalled reader to take what is
// queued: past it the rest is left unwritten.
constexpr auto kDrainWait = std::chrono::milliseconds(1000);

}  // namespace

struct LogWriter::Queue {
  Queue(size_t max, int out) : max_queued(max), fd(out) {}
  const size_t max_queued;
  const int fd;
  std::mutex mutex;
  std::condition_variable ready;
  std::condition_variable drained;
  std::deque<std::string> lines;
  bool stopping = false;
  bool writing = false;
  bool idle = false;  // the thread waits for lines: a new one must wake it
  std::atomic<uint64_t> dropped{0};
  std::atomic<uint64_t> written{0};

  void Run() {
    std::unique_lock lock(mutex);
    while (true) {
      idle = true;
      ready.wait(lock, [this] { return stopping || !lines.empty(); });
      idle = false;
      if (lines.empty()) {
        drained.notify_all();
        if (stopping) return;
        continue;
      }
      // A batch per write(): what is queued, some 64 KiB at most.
      std::string batch;
      uint64_t count = 0;
      while (!lines.empty() && batch.size() < 65536) {
        batch += lines.front();
        lines.pop_front();
        ++count;
      }
      writing = true;
      lock.unlock();
      size_t at = 0;
      while (at < batch.size()) {
        const ssize_t n = ::write(fd, batch.data() + at, batch.size() - at);
        if (n > 0) {
          at += static_cast<size_t>(n);
        } else if (n < 0 && errno == EINTR) {
          continue;
        } else {
          break;  // the reader is gone: nothing more to do for these lines
        }
      }
      written.fetch_add(count, std::memory_order_relaxed);
      lock.lock();
      writing = false;
      if (lines.empty()) drained.notify_all();
    }
  }
};

LogWriter::LogWriter(size_t max_queued_lines, int fd)
    : queue_(std::make_shared<Queue>(max_queued_lines, fd)), thread_([q = queue_] { q->Run(); }) {}

LogWriter::~LogWriter() {
  std::unique_lock lock(queue_->mutex);
  queue_->stopping = true;
  queue_->ready.notify_all();
  const bool done = queue_->drained.wait_for(
      lock, kDrainWait, [this] { return queue_->lines.empty() && !queue_->writing; });
  lock.unlock();
  if (done) {
    thread_.join();
  } else {
    // The reader has stalled: the thread is blocked in write(), holding the
    // queue, and ends with the process.
    thread_.detach();
  }
}

void LogWriter::Write(std::string line) {
  bool wake = false;
  {
    std::lock_guard lock(queue_->mutex);
    if (queue_->lines.size() >= queue_->max_queued) {
      queue_->dropped.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    line.push_back('\n');
    queue_->lines.push_back(std::move(line));
    // A thread at work takes this line with its next batch: only an idle
    // one is woken (a wake-up costs both threads a system call).
    wake = queue_->idle;
  }
  if (wake) queue_->ready.notify_one();
}

uint64_t LogWriter::dropped() const { return queue_->dropped.load(std::memory_order_relaxed); }
uint64_t LogWriter::written() const { return queue_->written.load(std::memory_order_relaxed); }

}  // namespace surfdeform::http
