#include "http/gate_stream.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace surfdeform::http {
namespace {

template <typename F>
void Address(int fd, F get, std::string& ip, int& port) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  ip.clear();
  port = 0;
  if (get(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return;
  char host[NI_MAXHOST];
  char serv[NI_MAXSERV];
  if (getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof host, serv, sizeof serv,
                  NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
    ip = host;
    port = std::atoi(serv);
  }
}

}  // namespace

GateStream::GateStream(int fd, std::chrono::seconds read_timeout,
                       std::chrono::seconds write_timeout, std::string preloaded,
                       OutputBudget* budget)
    : fd_(fd),
      read_ms_(static_cast<int>(read_timeout.count() * 1000)),
      write_ms_(static_cast<int>(write_timeout.count() * 1000)),
      preloaded_(std::move(preloaded)),
      budget_(budget) {}

GateStream::~GateStream() {
  if (budget_ != nullptr) budget_->Give(deferred_.size());
}

bool GateStream::is_readable() const { return buffered() > 0 || Poll(POLLIN, read_ms_); }

bool GateStream::is_writable() const {
  return budget_ != nullptr || !deferred_.empty() || Poll(POLLOUT, write_ms_);
}

// A body arrives in httplib's 4 KiB reads; they are served from a 64 KiB
// buffer, filled by a recv() that is tried before any poll(): a request with
// the 1.4 MB bunny took ~725 recv() and poll() calls before, ~37 now
// (strace -c; BENCHMARKS.md). A read of at least the buffer's size skips it.
ssize_t GateStream::read(char* ptr, size_t size) {
  const ssize_t n = ReadSome(ptr, size);
  if (n > 0) bytes_in_ += static_cast<size_t>(n);
  return n;
}

ssize_t GateStream::ReadSome(char* ptr, size_t size) {
  if (preloaded_at_ < preloaded_.size()) {
    const size_t n = std::min(size, preloaded_.size() - preloaded_at_);
    std::memcpy(ptr, preloaded_.data() + preloaded_at_, n);
    preloaded_at_ += n;
    if (preloaded_at_ == preloaded_.size()) {
      std::string().swap(preloaded_);  // a body's copy is freed once httplib has it
      preloaded_at_ = 0;
    }
    return static_cast<ssize_t>(n);
  }
  if (end_ == begin_) {
    const bool direct = size >= kBufferBytes;
    char* into = direct ? ptr : buffer_.get();
    const size_t room = direct ? size : kBufferBytes;
    ssize_t n = Recv(into, room, MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (!Poll(POLLIN, read_ms_)) return -1;
      n = Recv(into, room, 0);
    }
    if (n <= 0 || direct) return n;
    begin_ = 0;
    end_ = static_cast<size_t>(n);
  }
  const size_t n = std::min(size, end_ - begin_);
  std::memcpy(ptr, buffer_.get() + begin_, n);
  begin_ += n;
  return static_cast<ssize_t>(n);
}

ssize_t GateStream::write(const char* ptr, size_t size) {
  bytes_out_ += size;
  size_t sent = 0;
  if (deferred_.empty()) {
    const ssize_t n = SendNow(ptr, size);
    if (n < 0) return -1;
    sent = static_cast<size_t>(n);
    if (sent == size) return static_cast<ssize_t>(size);
  }
  const size_t rest = size - sent;
  if (budget_ != nullptr && budget_->Take(rest)) {
    deferred_.append(ptr + sent, rest);
    return static_cast<ssize_t>(size);
  }
  // Past the budget: what is kept goes first, then this, waiting for the socket.
  if (!FlushDeferred() || !SendAll(ptr + sent, rest)) return -1;
  return static_cast<ssize_t>(size);
}

std::string GateStream::TakeDeferred() {
  std::string out;
  out.swap(deferred_);
  return out;
}

bool GateStream::FlushDeferred() {
  if (deferred_.empty()) return true;
  const bool ok = SendAll(deferred_.data(), deferred_.size());
  if (budget_ != nullptr) budget_->Give(deferred_.size());
  std::string().swap(deferred_);
  return ok;
}

void GateStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  Address(fd_, getpeername, ip, port);
}

void GateStream::get_local_ip_and_port(std::string& ip, int& port) const {
  Address(fd_, getsockname, ip, port);
}

bool GateStream::Poll(short events, int ms) const {
  pollfd p{fd_, events, 0};
  int r;
  do {
    r = poll(&p, 1, ms);
  } while (r < 0 && errno == EINTR);
  return r > 0 && (p.revents & (events | POLLHUP)) != 0 && (p.revents & POLLNVAL) == 0;
}

ssize_t GateStream::Recv(char* out, size_t size, int flags) const {
  ssize_t n;
  do {
    n = recv(fd_, out, size, flags);
  } while (n < 0 && errno == EINTR);
  return n;
}

ssize_t GateStream::SendNow(const char* ptr, size_t size) const {
  size_t sent = 0;
  while (sent < size) {
    const ssize_t n = send(fd_, ptr + sent, size - sent, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n > 0) {
      sent += static_cast<size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      break;
    } else {
      return -1;
    }
  }
  return static_cast<ssize_t>(sent);
}

bool GateStream::SendAll(const char* ptr, size_t size) const {
  size_t sent = 0;
  while (sent < size) {
    const ssize_t n = SendNow(ptr + sent, size - sent);
    if (n < 0) return false;
    sent += static_cast<size_t>(n);
    if (sent < size && !Poll(POLLOUT, write_ms_)) return false;
  }
  return true;
}

}  // namespace surfdeform::http
