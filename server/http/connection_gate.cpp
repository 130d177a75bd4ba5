#include "http/connection_gate.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string_view>

#include "base/header_lists.hpp"
#include "http/problem.hpp"

namespace surfdeform::http {
namespace {

using Clock = std::chrono::steady_clock;

// How long a worker waits after a response for the next request's head
// before it hands the connection back to the gate.
constexpr int kLingerMs = 1;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// The value of header `name` (case-insensitive) in a request head, or empty.
std::string_view HeaderValue(std::string_view head, std::string_view name) {
  size_t line = head.find("\r\n");
  while (line != std::string_view::npos && line + 2 < head.size()) {
    const size_t start = line + 2;
    const size_t end = head.find("\r\n", start);
    if (end == std::string_view::npos || end == start) break;
    const std::string_view text = head.substr(start, end - start);
    const size_t colon = text.find(':');
    if (colon == name.size() && EqualsIgnoringCase(text.substr(0, colon), name)) {
      return TrimHttpSpace(text.substr(colon + 1));
    }
    line = end;
  }
  return {};
}

// A plain decimal Content-Length, or -1 (absent, malformed: the framing
// checks answer those).
long long DeclaredLength(std::string_view head) {
  const std::string_view v = HeaderValue(head, "Content-Length");
  if (v.empty() || v.size() > 18) return -1;
  long long n = 0;
  for (char c : v) {
    if (c < '0' || c > '9') return -1;
    n = n * 10 + (c - '0');
  }
  return n;
}

}  // namespace

// A connection on a worker: its phase and when the phase began. The
// watchdog shuts down `fd`, a dup of the served socket, so that the socket
// cannot be closed and its number reused while the watchdog holds it.
struct ConnectionGate::Served {
  enum class Phase { kHead, kBody, kHandling, kResponding };
  std::mutex mutex;
  int fd = -1;
  Phase phase = Phase::kHead;
  Clock::time_point since;
  uint64_t expected = 0;  // body or response bytes
  uint64_t done = 0;      // body bytes read so far, where known
  bool progress_known = false;
  bool shut = false;
  bool close_after = false;  // the request could not be framed: end the connection
};

namespace {

thread_local ConnectionGate::Served* t_served = nullptr;

template <typename F>
void UpdatePhase(F&& f) {
  ConnectionGate::Served* s = t_served;
  if (s == nullptr) return;
  std::lock_guard lock(s->mutex);
  f(*s);
}

void SetPhase(ConnectionGate::Served& s, ConnectionGate::Served::Phase phase, uint64_t expected) {
  s.phase = phase;
  s.since = Clock::now();
  s.expected = expected;
  s.done = 0;
  s.progress_known = false;
}

// httplib's Stream over a socket, as its SocketStream (which 0.11.4 does not
// export): reads buffered, each recv() and send() bounded by a timeout.
class GateStream final : public httplib::Stream {
 public:
  GateStream(int fd, std::chrono::seconds read_timeout, std::chrono::seconds write_timeout)
      : fd_(fd),
        read_ms_(static_cast<int>(read_timeout.count() * 1000)),
        write_ms_(static_cast<int>(write_timeout.count() * 1000)) {}

  bool is_readable() const override { return buffered() > 0 || Poll(POLLIN, read_ms_); }
  bool is_writable() const override { return Poll(POLLOUT, write_ms_); }

  // A body arrives in httplib's 4 KiB reads; they are served from a 64 KiB
  // buffer, filled by a recv() that is tried before any poll(): a request
  // with the 1.4 MB bunny took ~725 recv() and poll() calls before, ~37 now
  // (strace -c; BENCHMARKS.md). A read of at least the buffer's size skips it.
  ssize_t read(char* ptr, size_t size) override {
    if (buffered() == 0) {
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
    const size_t n = std::min(size, buffered());
    std::memcpy(ptr, buffer_.get() + begin_, n);
    begin_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (!Poll(POLLOUT, write_ms_)) return -1;
    ssize_t n;
    do {
      n = send(fd_, ptr, size, MSG_NOSIGNAL);
    } while (n < 0 && errno == EINTR);
    return n;
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    Address(getpeername, ip, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    Address(getsockname, ip, port);
  }
  socket_t socket() const override { return fd_; }

  size_t buffered() const { return end_ - begin_; }

 private:
  bool Poll(short events, int ms) const {
    pollfd p{fd_, events, 0};
    int r;
    do {
      r = poll(&p, 1, ms);
    } while (r < 0 && errno == EINTR);
    return r > 0 && (p.revents & (events | POLLHUP)) != 0 && (p.revents & POLLNVAL) == 0;
  }
  ssize_t Recv(char* out, size_t size, int flags) const {
    ssize_t n;
    do {
      n = recv(fd_, out, size, flags);
    } while (n < 0 && errno == EINTR);
    return n;
  }
  template <typename F>
  void Address(F get, std::string& ip, int& port) const {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    ip.clear();
    port = 0;
    if (get(fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return;
    char host[NI_MAXHOST];
    char serv[NI_MAXSERV];
    if (getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof host, serv, sizeof serv,
                    NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
      ip = host;
      port = std::atoi(serv);
    }
  }

  int fd_;
  int read_ms_;
  int write_ms_;
  static constexpr size_t kBufferBytes = 64 * 1024;
  // Not zeroed: a stream is made each time a connection comes to a worker.
  std::unique_ptr<char[]> buffer_ = std::make_unique_for_overwrite<char[]>(kBufferBytes);
  size_t begin_ = 0;
  size_t end_ = 0;
};

}  // namespace

namespace connection_phase {
void HeadIn(size_t content_length) {
  UpdatePhase([&](ConnectionGate::Served& s) {
    SetPhase(s, ConnectionGate::Served::Phase::kBody, content_length);
  });
}
void BodyProgress(size_t bytes) {
  UpdatePhase([&](ConnectionGate::Served& s) {
    s.done = bytes;
    s.progress_known = true;
  });
}
void Handling() {
  UpdatePhase(
      [](ConnectionGate::Served& s) { SetPhase(s, ConnectionGate::Served::Phase::kHandling, 0); });
}
void Responding(size_t bytes) {
  UpdatePhase([&](ConnectionGate::Served& s) {
    SetPhase(s, ConnectionGate::Served::Phase::kResponding, bytes);
  });
}
void CloseAfterResponse() {
  UpdatePhase([](ConnectionGate::Served& s) { s.close_after = true; });
}
}  // namespace connection_phase

ConnectionGate::ConnectionGate(GateOptions options, ServeRequest serve)
    : options_(options),
      serve_(std::move(serve)),
      pool_(std::make_unique<httplib::ThreadPool>(static_cast<size_t>(options.workers))) {
  epoll_fd_ = epoll_create1(EPOLL_CLOEXEC);
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.fd = wake_fd_;
  epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, wake_fd_, &ev);
  loop_ = std::thread([this] { Loop(); });
}

ConnectionGate::~ConnectionGate() {
  shutdown();
  if (epoll_fd_ >= 0) close(epoll_fd_);
  if (wake_fd_ >= 0) close(wake_fd_);
}

void ConnectionGate::shutdown() {
  if (stopping_.exchange(true)) return;
  const uint64_t one = 1;
  [[maybe_unused]] auto n = write(wake_fd_, &one, sizeof one);
  if (loop_.joinable()) loop_.join();
  pool_->shutdown();  // requests on workers finish; their connections close
  std::lock_guard lock(mutex_);
  for (const auto& [fd, pending] : waiting_) close(fd);  // no request under way
  for (const auto& [fd, pending] : admitted_) close(fd);
  waiting_.clear();
  admitted_.clear();
}

void ConnectionGate::Admit(int fd) {
  if (options_.send_buffer_bytes > 0) {
    setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &options_.send_buffer_bytes,
               sizeof options_.send_buffer_bytes);
  }
  Wait(fd, options_.max_requests_per_connection, false);
}

void ConnectionGate::Wait(int fd, int requests_left, bool kept_alive) {
  bool refuse = false;
  {
    std::lock_guard lock(mutex_);
    if (stopping_.load()) {
      close(fd);
      return;
    }
    // Past max_waiting the loop closes the longest waiting to make room;
    // past the margin it has not caught up with a burst.
    if (!kept_alive && waiting_.size() + admitted_.size() >= BurstLimit()) {
      ++stats_.refused_full;
      refuse = true;
    } else {
      admitted_.emplace_back(fd, Pending{Clock::now(), requests_left, kept_alive, false});
    }
  }
  if (refuse) {
    Refuse(
        fd, 503,
        Status(ErrorCode::kUnavailable,
               "too many connections are waiting to send their requests; retry later")
            .WithLimit(static_cast<double>(BurstLimit()), static_cast<double>(BurstLimit() + 1)));
    return;
  }
  const uint64_t one = 1;
  [[maybe_unused]] auto n = write(wake_fd_, &one, sizeof one);
}

ConnectionStats ConnectionGate::stats() const {
  std::lock_guard lock(mutex_);
  ConnectionStats s = stats_;
  s.waiting = waiting_.size() + admitted_.size();
  s.served = served_.size();
  return s;
}

ConnectionGate::Verdict ConnectionGate::Inspect(int fd, size_t* seen,
                                                std::optional<Rejection>* rejection) const {
  // The head and the body's first window, without taking them off the socket.
  thread_local std::vector<char> buffer;
  buffer.resize(options_.max_head_bytes + options_.body_window_bytes);
  const ssize_t n = recv(fd, buffer.data(), buffer.size(), MSG_PEEK | MSG_DONTWAIT);
  if (n == 0) return Verdict::kClosed;
  if (n < 0) {
    return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? Verdict::kWait
                                                                     : Verdict::kClosed;
  }
  const std::string_view bytes(buffer.data(), static_cast<size_t>(n));
  *seen = bytes.size();
  const size_t end = bytes.find("\r\n\r\n");
  *rejection = CheckHead(bytes, end == std::string_view::npos ? kHeadIncomplete : end + 4);
  if (*rejection) return Verdict::kMalformed;
  if (end == std::string_view::npos || end + 4 > options_.max_head_bytes) {
    return bytes.size() >= options_.max_head_bytes ? Verdict::kTooLarge : Verdict::kWait;
  }
  const std::string_view head = bytes.substr(0, end + 4);
  const long long length = DeclaredLength(head);
  if (length <= 0 || static_cast<unsigned long long>(length) > options_.max_body_bytes) {
    return Verdict::kPass;
  }
  if (!HeaderValue(head, "Expect").empty()) return Verdict::kPass;  // waits for 100 Continue
  const size_t want = std::min<size_t>(static_cast<size_t>(length), options_.body_window_bytes);
  return bytes.size() - head.size() >= want ? Verdict::kPass : Verdict::kWait;
}

void ConnectionGate::Refuse(int fd, int http_status, const Status& status) {
  const std::string body = ProblemJson(status, http_status, "", "");
  // A refusal for load says when to come back (the gate keeps no service
  // time: a second, as a busy admission's shortest answer).
  const std::string retry = http_status == 503 ? "\r\nRetry-After: 1" : "";
  const std::string response = "HTTP/1.1 " + std::to_string(http_status) + " " +
                               StatusTitle(http_status) + "\r\nContent-Type: " + kProblemType +
                               "\r\nContent-Length: " + std::to_string(body.size()) + retry +
                               "\r\nConnection: close\r\n\r\n" + body;
  // Best effort, never blocking: the client may have stopped reading.
  [[maybe_unused]] auto n = send(fd, response.data(), response.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
  ::shutdown(fd, SHUT_WR);
  close(fd);
}

void ConnectionGate::ServeOnWorker(int fd, int requests_left) {
  auto served = std::make_shared<Served>();
  served->fd = dup(fd);
  served->since = Clock::now();
  uint64_t id;
  {
    std::lock_guard lock(mutex_);
    id = next_served_id_++;
    served_.emplace(id, served);
  }
  t_served = served.get();
  GateStream stream(fd, options_.read_timeout, options_.write_timeout);
  bool keep = false;
  while (true) {
    {
      std::lock_guard lock(served->mutex);
      SetPhase(*served, Served::Phase::kHead, 0);
    }
    const bool close_connection = requests_left <= 1 || stopping_.load();
    bool connection_closed = false;
    const bool ok = serve_(stream, close_connection, connection_closed);
    --requests_left;
    bool shut;
    {
      std::lock_guard lock(served->mutex);
      shut = served->shut || served->close_after;
    }
    if (!ok || connection_closed || close_connection || shut) break;
    if (stream.buffered() == 0) {
      // A client that sends its next request at once (a load generator, a
      // browser's next fetch) keeps the worker if the whole head is in
      // within a millisecond: handing it to the gate and back would cost
      // a quarter of a small request's throughput. Anything less waits in
      // the gate.
      pollfd p{fd, POLLIN, 0};
      size_t seen = 0;
      std::optional<Rejection> rejection;
      if (poll(&p, 1, kLingerMs) == 1 && (p.revents & POLLIN) != 0 &&
          Inspect(fd, &seen, &rejection) == Verdict::kPass) {
        continue;
      }
      keep = true;
      break;
    }
  }
  t_served = nullptr;
  {
    std::lock_guard lock(mutex_);
    served_.erase(id);
  }
  {
    std::lock_guard lock(served->mutex);
    if (served->fd >= 0) close(served->fd);
    served->fd = -1;
  }
  if (keep) {
    Wait(fd, requests_left, true);
  } else {
    ::shutdown(fd, SHUT_RDWR);
    close(fd);
  }
}

void ConnectionGate::CheckDeadlines(Clock::time_point now) {
  std::vector<std::pair<int, bool>> expired;  // fd, answer 408
  std::vector<std::shared_ptr<Served>> served;
  {
    std::lock_guard lock(mutex_);
    for (auto it = waiting_.begin(); it != waiting_.end();) {
      const Pending& p = it->second;
      const auto age = now - p.since;
      const bool idle_over = p.kept_alive && !p.started && age >= options_.idle_timeout;
      const auto budget =
          p.kept_alive ? options_.idle_timeout + options_.head_timeout : options_.head_timeout;
      if (idle_over || age >= budget) {
        expired.emplace_back(it->first, p.started);
        ++(idle_over ? stats_.idle : stats_.head_timeout);
        it = waiting_.erase(it);
      } else {
        ++it;
      }
    }
    served.reserve(served_.size());
    for (const auto& [id, s] : served_) served.push_back(s);
  }
  for (const auto& [fd, answer] : expired) {
    epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
    if (!answer) {  // nothing was sent: close quietly, as after a keep-alive wait
      close(fd);
      continue;
    }
    const double ms = std::chrono::duration<double, std::milli>(options_.head_timeout).count();
    Refuse(fd, 408,
           Status::DeadlineExceeded("the request head (through its blank line) and the start of "
                                    "its body must arrive within the head timeout",
                                    "", ms, ms));
  }
  using Phase = Served::Phase;
  for (const auto& s : served) {
    std::lock_guard lock(s->mutex);
    if (s->shut || s->fd < 0) continue;
    const double t = Seconds(now - s->since);
    const double paced = options_.min_bytes_per_s * (t - Seconds(options_.transfer_grace));
    uint64_t* counter = nullptr;
    switch (s->phase) {
      case Phase::kHead:  // a pipelined request's head
        if (t > Seconds(options_.head_timeout)) counter = &stats_.head_timeout;
        break;
      case Phase::kBody:
        // Where the handler reports progress, the bytes so far must keep
        // pace; where httplib reads the body, all of it must be in by then.
        if (paced > static_cast<double>(s->progress_known ? s->done : s->expected)) {
          counter = &stats_.slow_body;
        }
        break;
      case Phase::kResponding:
        if (paced > static_cast<double>(s->expected)) counter = &stats_.slow_response;
        break;
      case Phase::kHandling:
        break;
    }
    if (counter == nullptr) continue;
    // An abortive close once the worker lets go (as nginx's
    // reset_timedout_connection): what is still queued for a slow reader is
    // dropped with an RST and its kernel memory freed, rather than trickled
    // out to the client after the cut.
    const linger abort{1, 0};
    setsockopt(s->fd, SOL_SOCKET, SO_LINGER, &abort, sizeof abort);
    ::shutdown(s->fd, SHUT_RDWR);  // the worker's blocked recv or send returns
    s->shut = true;
    std::lock_guard stats_lock(mutex_);
    ++*counter;
  }
}

void ConnectionGate::EvictLongestWaiting() {
  std::vector<std::pair<int, bool>> evicted;  // fd, some of a head had come
  {
    std::lock_guard lock(mutex_);
    while (waiting_.size() > options_.max_waiting) {
      // An idle kept-alive connection first (its client reconnects at no
      // loss), else the one that has waited longest.
      auto victim = waiting_.end();
      for (auto it = waiting_.begin(); it != waiting_.end(); ++it) {
        const bool idle = it->second.kept_alive && !it->second.started;
        const bool victim_idle =
            victim != waiting_.end() && victim->second.kept_alive && !victim->second.started;
        if (victim == waiting_.end() || (idle && !victim_idle) ||
            (idle == victim_idle && it->second.since < victim->second.since)) {
          victim = it;
        }
      }
      evicted.emplace_back(victim->first, victim->second.started);
      waiting_.erase(victim);
      ++stats_.evicted;
    }
  }
  for (const auto& [fd, started] : evicted) {
    epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
    if (!started) {
      close(fd);
      continue;
    }
    Refuse(fd, 503,
           Status(ErrorCode::kUnavailable,
                  "too many connections are waiting to send their requests, and this one had "
                  "waited longest; retry later")
               .WithLimit(static_cast<double>(options_.max_waiting),
                          static_cast<double>(options_.max_waiting + 1)));
  }
}

void ConnectionGate::Loop() {
  constexpr int kMaxEvents = 64;
  epoll_event events[kMaxEvents];
  auto next_check = Clock::now();
  while (!stopping_.load()) {
    const int n = epoll_wait(epoll_fd_, events, kMaxEvents, 100);
    std::vector<std::pair<int, Pending>> admitted;
    {
      std::lock_guard lock(mutex_);
      admitted.swap(admitted_);
      for (const auto& [fd, pending] : admitted) waiting_.emplace(fd, pending);
    }
    EvictLongestWaiting();
    for (const auto& [fd, pending] : admitted) {
      epoll_event ev{};
      ev.events = EPOLLIN | EPOLLRDHUP | EPOLLET;  // each arrival, though unread
      ev.data.fd = fd;
      epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, fd, &ev);  // reports bytes already there
    }
    for (int k = 0; k < n; ++k) {
      const int fd = events[k].data.fd;
      if (fd == wake_fd_) {
        uint64_t count;
        [[maybe_unused]] auto r = read(wake_fd_, &count, sizeof count);
        continue;
      }
      size_t seen = 0;
      std::optional<Rejection> rejection;
      const Verdict verdict = Inspect(fd, &seen, &rejection);
      int requests_left = 0;
      {
        std::lock_guard lock(mutex_);
        auto it = waiting_.find(fd);
        if (it == waiting_.end()) continue;  // timed out already
        if (seen > 0) it->second.started = true;
        if (verdict == Verdict::kWait) continue;
        requests_left = it->second.requests_left;
        waiting_.erase(it);
        if (verdict == Verdict::kTooLarge) ++stats_.head_too_large;
        if (verdict == Verdict::kMalformed) ++stats_.malformed_head;
        if (verdict == Verdict::kClosed) ++stats_.closed_early;
        if (verdict == Verdict::kPass) ++stats_.passed;
      }
      epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
      switch (verdict) {
        case Verdict::kPass:
          pool_->enqueue([this, fd, requests_left] { ServeOnWorker(fd, requests_left); });
          break;
        case Verdict::kTooLarge:
          Refuse(fd, 431,
                 Status::LimitExceeded("the request head is too large", "",
                                       static_cast<double>(options_.max_head_bytes),
                                       static_cast<double>(seen)));
          break;
        case Verdict::kMalformed:
          Refuse(fd, rejection->http_status, rejection->status);
          break;
        default:
          close(fd);
          break;
      }
    }
    const auto now = Clock::now();
    if (now >= next_check) {
      CheckDeadlines(now);
      next_check = now + std::chrono::milliseconds(100);
    }
  }
}

}  // namespace surfdeform::http
