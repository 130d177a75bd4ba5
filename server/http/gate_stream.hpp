// httplib's Stream over a connection's socket, as the connection gate serves
// it on a worker (httplib 0.11.4 does not export its own SocketStream).
//
// - Reads come first from the bytes the gate read already (a request's head
//   and body, read off the workers), then from the socket: buffered, each
//   recv() bounded by the read timeout.
// - Writes go to the socket as far as it takes them at once; the rest is
//   kept (within the gate's output budget) for the gate to send off the
//   workers, so that a client that reads slowly never holds a worker. Past
//   the budget a write waits for the socket, as a plain blocking write.
#pragma once

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include "base/shared_budget.hpp"

namespace surfdeform::http {

// Bytes of responses kept for slow readers, across connections.
using OutputBudget = SharedBudget;

class GateStream final : public httplib::Stream {
 public:
  // `preloaded`: bytes of the connection read already, served first.
  // `budget` (may be null: every write waits for the socket).
  GateStream(int fd, std::chrono::seconds read_timeout, std::chrono::seconds write_timeout,
             std::string preloaded, OutputBudget* budget);
  ~GateStream() override;

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return fd_; }

  // Bytes read from the connection but not yet taken by httplib.
  size_t buffered() const { return preloaded_.size() - preloaded_at_ + (end_ - begin_); }
  // The response bytes the socket has not taken: the gate sends them. The
  // budget they hold passes with them (OutputBudget::Give once sent).
  std::string TakeDeferred();
  bool has_deferred() const { return !deferred_.empty(); }
  // Bytes read and written since the last ResetCounts().
  size_t bytes_in() const { return bytes_in_; }
  size_t bytes_out() const { return bytes_out_; }
  void ResetCounts() { bytes_in_ = bytes_out_ = 0; }
  // Waits (within the write timeout per send) until every deferred byte is
  // out; false when the connection failed.
  bool FlushDeferred();

 private:
  ssize_t ReadSome(char* ptr, size_t size);
  bool Poll(short events, int ms) const;
  ssize_t Recv(char* out, size_t size, int flags) const;
  // Sends what the socket takes now; the count sent, or -1 on an error.
  ssize_t SendNow(const char* ptr, size_t size) const;
  bool SendAll(const char* ptr, size_t size) const;  // blocking, within the write timeout

  int fd_;
  int read_ms_;
  int write_ms_;
  std::string preloaded_;
  size_t preloaded_at_ = 0;
  OutputBudget* budget_;
  std::string deferred_;  // holds budget_ for its size
  static constexpr size_t kBufferBytes = 64 * 1024;
  // Not zeroed: a stream is made each time a connection comes to a worker.
  std::unique_ptr<char[]> buffer_ = std::make_unique_for_overwrite<char[]>(kBufferBytes);
  size_t begin_ = 0;
  size_t end_ = 0;
  size_t bytes_in_ = 0;
  size_t bytes_out_ = 0;
};

}  // namespace surfdeform::http
