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
#include "service/allocator_tuning.hpp"

namespace surfdeform::http {
namespace {

using Clock = std::chrono::steady_clock;

// How long a worker waits after a response for the next request's head
// before it hands the connection back to the gate.
constexpr int kLingerMs = 1;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// The value of header `name` (case-insensitive) in a request head, when
// the head has it.
std::optional<std::string_view> FindHeader(std::string_view head, std::string_view name) {
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
  return std::nullopt;
}

// Its value, or empty.
std::string_view HeaderValue(std::string_view head, std::string_view name) {
  return FindHeader(head, name).value_or(std::string_view());
}

bool HasHeader(std::string_view head, std::string_view name) {
  return FindHeader(head, name).has_value();
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

// The head without its Expect field line (the gate answered it: httplib
// must not send a second 100 Continue).
std::string WithoutExpect(std::string_view head) {
  std::string out;
  size_t at = 0;
  while (at < head.size()) {
    const size_t end = head.find("\r\n", at);
    const size_t next = end == std::string_view::npos ? head.size() : end + 2;
    const std::string_view line = head.substr(at, next - at);
    const size_t colon = line.find(':');
    if (at == 0 || colon != 6 || !EqualsIgnoringCase(line.substr(0, 6), "Expect")) out += line;
    at = next;
  }
  return out;
}

// The method and path of a request head's first line.
void RequestLineOf(std::string_view head, std::string_view* method, std::string_view* path) {
  const std::string_view line = head.substr(0, head.find("\r\n"));
  const size_t sp1 = line.find(' ');
  const size_t sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
  *method = line.substr(0, sp1);
  *path = sp2 == std::string_view::npos ? std::string_view() : line.substr(sp1 + 1, sp2 - sp1 - 1);
  *path = path->substr(0, path->find('?'));
}

// The peer's address, for the bodies-per-address limit.
std::string PeerAddress(int fd) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  if (getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return "?";
  char host[NI_MAXHOST];
  if (getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof host, nullptr, 0,
                  NI_NUMERICHOST) != 0) {
    return "?";
  }
  return host;
}

// An abortive close (as nginx's reset_timedout_connection): what is still
// queued for a slow reader is dropped with an RST and its kernel memory
// freed, rather than trickled out to the client after the cut.
void ResetAndClose(int fd) {
  const linger abort{1, 0};
  setsockopt(fd, SOL_SOCKET, SO_LINGER, &abort, sizeof abort);
  close(fd);
}

Clock::time_point TransferDeadline(Clock::time_point now, size_t bytes, const GateOptions& options,
                                   Clock::duration cap) {
  const auto pace = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(static_cast<double>(bytes) / options.min_bytes_per_s));
  return now + std::min<Clock::duration>(options.transfer_grace + pace, cap);
}

}  // namespace

// A connection on a worker: its phase and when the phase began. The
// watchdog shuts down `fd`, a dup of the served socket, so that the socket
// cannot be closed and its number reused while the watchdog holds it.
struct ConnectionGate::Served {
  enum class Phase { kHead, kBody, kHandling, kResponding };
  explicit Served(const CancelFlag* stopping) : cancel(stopping) {}
  std::mutex mutex;
  int fd = -1;
  Phase phase = Phase::kHead;
  Clock::time_point since;
  uint64_t expected = 0;  // body or response bytes
  uint64_t done = 0;      // body bytes read so far, where known
  bool progress_known = false;
  bool shut = false;
  bool close_after = false;  // the request could not be framed: end the connection
  CancelFlag cancel;         // raised when the client hangs up while a request is handled
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
const CancelFlag* Cancel() { return t_served != nullptr ? &t_served->cancel : nullptr; }
}  // namespace connection_phase

ConnectionGate::ConnectionGate(GateOptions options, ServeRequest serve)
    : options_(options),
      serve_(std::move(serve)),
      pool_(std::make_unique<httplib::ThreadPool>(static_cast<size_t>(options.workers))),
      probe_pool_(std::make_unique<httplib::ThreadPool>(
          static_cast<size_t>(std::max(1, options.probe_workers)))),
      output_budget_(options.max_output_buffer_bytes) {
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
  probe_pool_->shutdown();
  std::lock_guard lock(mutex_);
  for (const auto& [fd, pending] : waiting_) close(fd);  // no request under way
  for (const auto& [fd, pending] : admitted_) close(fd);
  for (const auto& [fd, reading] : reading_) close(fd);
  for (const auto& [fd, flushing] : flushing_) {
    output_budget_.Give(flushing.bytes.size());
    close(fd);
  }
  for (const auto& [fd, flushing] : handed_over_) {
    output_budget_.Give(flushing.bytes.size());
    close(fd);
  }
  waiting_.clear();
  admitted_.clear();
  reading_.clear();
  flushing_.clear();
  handed_over_.clear();
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
  s.output_buffer_bytes = output_budget_.held();
  return s;
}

ConnectionGate::Inspection ConnectionGate::Inspect(int fd) const {
  Inspection in;
  // The head and the body's first window, without taking them off the socket.
  thread_local std::vector<char> buffer;
  buffer.resize(options_.max_head_bytes + options_.body_window_bytes);
  const ssize_t n = recv(fd, buffer.data(), buffer.size(), MSG_PEEK | MSG_DONTWAIT);
  if (n == 0) {
    in.verdict = Verdict::kClosed;
    return in;
  }
  if (n < 0) {
    const bool again = errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
    in.verdict = again ? Verdict::kWait : Verdict::kClosed;
    return in;
  }
  const std::string_view bytes(buffer.data(), static_cast<size_t>(n));
  in.seen = bytes.size();
  const size_t end = bytes.find("\r\n\r\n");
  in.rejection = CheckHead(bytes, end == std::string_view::npos ? kHeadIncomplete : end + 4);
  if (in.rejection) {
    in.verdict = Verdict::kMalformed;
    return in;
  }
  if (end == std::string_view::npos || end + 4 > options_.max_head_bytes) {
    in.verdict = bytes.size() >= options_.max_head_bytes ? Verdict::kTooLarge : Verdict::kWait;
    return in;
  }
  const std::string_view head = bytes.substr(0, end + 4);
  in.head_bytes = head.size();
  std::string_view method, path;
  RequestLineOf(head, &method, &path);
  const long long length = DeclaredLength(head);
  const bool declares_body = length > 0 || HasHeader(head, "Transfer-Encoding") ||
                             (length < 0 && HasHeader(head, "Content-Length"));
  if (declares_body &&
      (method == "GET" || method == "HEAD" || method == "OPTIONS" || method == "TRACE")) {
    // httplib 0.11.4 does not read a body on these methods: left on the
    // connection, it would be read as the next request (request smuggling
    // behind a proxy that keeps its upstream connections alive).
    in.verdict = Verdict::kMalformed;
    in.body_not_allowed = true;
    in.rejection =
        Rejection{400, Status(ErrorCode::kMalformed,
                              std::string(method) +
                                  " requests take no body; send it without Content-Length or "
                                  "Transfer-Encoding",
                              "Content-Length")};
    return in;
  }
  if (!declares_body && method == "GET" && (path == "/healthz" || path == "/readyz")) {
    in.verdict = Verdict::kProbe;
    return in;
  }
  if (length <= 0 || static_cast<unsigned long long>(length) > options_.max_body_bytes) {
    in.verdict = Verdict::kPass;  // no body, or one the framing checks refuse
    return in;
  }
  in.body_bytes = static_cast<size_t>(length);
  in.expect_continue = !HeaderValue(head, "Expect").empty();
  if (!in.expect_continue && in.body_bytes <= options_.body_window_bytes) {
    in.verdict = bytes.size() - head.size() >= in.body_bytes ? Verdict::kPass : Verdict::kWait;
    return in;
  }
  in.verdict = Verdict::kBody;
  return in;
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

void ConnectionGate::ServeOnWorker(int fd, int requests_left, std::string preloaded, bool probe) {
  auto served = std::make_shared<Served>(options_.stopping);
  served->fd = dup(fd);
  served->since = Clock::now();
  uint64_t id;
  {
    std::lock_guard lock(mutex_);
    id = next_served_id_++;
    served_.emplace(id, served);
  }
  t_served = served.get();
  GateStream stream(fd, options_.read_timeout, options_.write_timeout, std::move(preloaded),
                    probe ? nullptr : &output_budget_);
  // A probe's connection serves that request alone (the probe worker
  // serves nothing else).
  if (probe) requests_left = 1;
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
    // The request's buffers are gone: after a large one, its memory goes
    // back to the kernel (allocator_tuning.hpp).
    if (stream.bytes_in() >= kLargeRequestBytes || stream.bytes_out() >= kLargeRequestBytes) {
      MarkLargeRequest();
    }
    stream.ResetCounts();
    ReleaseAfterLargeRequest();
    bool shut;
    {
      std::lock_guard lock(served->mutex);
      shut = served->shut || served->close_after;
    }
    if (!ok || connection_closed || close_connection || shut) break;
    if (stream.buffered() > 0) {
      // A pipelined request's bytes are in the stream: this worker serves
      // it, once the response before it is out.
      if (!stream.FlushDeferred()) break;
      continue;
    }
    keep = true;
    // A client that reads slowly: the gate sends the rest of the response,
    // then waits for its next request.
    if (stream.has_deferred()) break;
    // A client that sends its next request at once (a load generator, a
    // browser's next fetch) keeps the worker if the whole head is in within
    // a millisecond: handing it to the gate and back would cost a quarter
    // of a small request's throughput. Anything less waits in the gate.
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, kLingerMs) == 1 && (p.revents & POLLIN) != 0 &&
        Inspect(fd).verdict == Verdict::kPass) {
      continue;
    }
    break;
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
  std::string deferred = stream.TakeDeferred();
  if (!deferred.empty()) {
    // The response's rest goes out from the gate; then the connection ends,
    // or waits there for its next request.
    StartFlushing(fd, std::move(deferred), requests_left, !keep);
    return;
  }
  if (keep) {
    Wait(fd, requests_left, true);
  } else {
    ::shutdown(fd, SHUT_RDWR);
    close(fd);
  }
}

void ConnectionGate::Watch(int fd, uint32_t events) {
  epoll_event ev{};
  ev.events = events | EPOLLRDHUP | EPOLLET;
  ev.data.fd = fd;
  if (epoll_ctl(epoll_fd_, EPOLL_CTL_MOD, fd, &ev) != 0) {
    epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, fd, &ev);
  }
}

void ConnectionGate::StartReading(int fd, const Inspection& in, int requests_left) {
  std::string address = PeerAddress(fd);
  int& from_address = readers_by_address_[address];
  const bool over_address = from_address >= options_.max_bodies_per_address;
  const bool over_total = reading_bytes_ + in.body_bytes > options_.max_body_buffer_bytes;
  if (over_address || over_total) {
    if (from_address == 0) readers_by_address_.erase(address);
    {
      std::lock_guard lock(mutex_);
      ++stats_.bodies_refused;
    }
    epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
    Refuse(fd, 503,
           over_address
               ? Status(ErrorCode::kUnavailable,
                        "this client address is sending " + std::to_string(from_address) +
                            " request bodies at once, the most the server reads from one "
                            "address; retry when one is done",
                        "Content-Length")
                     .WithLimit(options_.max_bodies_per_address, from_address + 1)
               : Status(ErrorCode::kUnavailable,
                        "the server is reading as many request bodies as it may hold; retry "
                        "later",
                        "Content-Length")
                     .WithLimit(static_cast<double>(options_.max_body_buffer_bytes),
                                static_cast<double>(reading_bytes_ + in.body_bytes)));
    return;
  }
  // The head off the socket (it was only peeked), then the body as it comes.
  Reading r;
  r.bytes.resize(in.head_bytes);
  size_t got = 0;
  while (got < in.head_bytes) {
    const ssize_t n = recv(fd, r.bytes.data() + got, in.head_bytes - got, MSG_DONTWAIT);
    if (n <= 0) {
      if (from_address == 0) readers_by_address_.erase(address);
      epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
      close(fd);
      return;
    }
    got += static_cast<size_t>(n);
  }
  if (in.expect_continue) {
    // Answered here (the client waits for it before it sends the body);
    // httplib must not answer it again.
    r.bytes = WithoutExpect(r.bytes);
    static constexpr std::string_view kContinue = "HTTP/1.1 100 Continue\r\n\r\n";
    [[maybe_unused]] auto n =
        send(fd, kContinue.data(), kContinue.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
  }
  r.head = r.bytes.size();
  r.need = r.head + in.body_bytes;
  r.bytes.reserve(r.need);
  r.since = Clock::now();
  r.address = std::move(address);
  r.declared = in.body_bytes;
  r.requests_left = requests_left;
  ++from_address;
  reading_bytes_ += in.body_bytes;
  reading_.emplace(fd, std::move(r));
  OnReading(fd);  // what is in already
}

void ConnectionGate::OnReading(int fd) {
  auto it = reading_.find(fd);
  if (it == reading_.end()) return;
  Reading& r = it->second;
  while (r.bytes.size() < r.need) {
    const size_t old = r.bytes.size();
    r.bytes.resize(r.need);
    const ssize_t n = recv(fd, r.bytes.data() + old, r.need - old, MSG_DONTWAIT);
    r.bytes.resize(old + static_cast<size_t>(std::max<ssize_t>(n, 0)));
    if (n > 0) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
    // The client left mid-body: nobody to answer.
    epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
    close(fd);
    EndReading(it);
    return;
  }
  epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
  std::string bytes = std::move(r.bytes);
  const int requests_left = r.requests_left;
  EndReading(it);
  {
    std::lock_guard lock(mutex_);
    ++stats_.bodies_read;
    ++stats_.passed;
  }
  pool_->enqueue([this, fd, requests_left, b = std::move(bytes)]() mutable {
    ServeOnWorker(fd, requests_left, std::move(b), false);
  });
}

void ConnectionGate::EndReading(std::map<int, Reading>::iterator it) {
  auto address = readers_by_address_.find(it->second.address);
  if (address != readers_by_address_.end() && --address->second <= 0) {
    readers_by_address_.erase(address);
  }
  reading_bytes_ -= it->second.declared;
  reading_.erase(it);
}

void ConnectionGate::StartFlushing(int fd, std::string bytes, int requests_left, bool close_after) {
  Flushing f;
  f.bytes = std::move(bytes);
  f.deadline = TransferDeadline(Clock::now(), f.bytes.size(), options_, Clock::duration::max());
  f.requests_left = requests_left;
  f.close_after = close_after;
  {
    std::lock_guard lock(mutex_);
    ++stats_.responses_kept;
    handed_over_.emplace_back(fd, std::move(f));
  }
  const uint64_t one = 1;
  [[maybe_unused]] auto n = write(wake_fd_, &one, sizeof one);
}

void ConnectionGate::OnFlushing(int fd) {
  auto it = flushing_.find(fd);
  if (it == flushing_.end()) return;
  Flushing& f = it->second;
  while (f.sent < f.bytes.size()) {
    const ssize_t n =
        send(fd, f.bytes.data() + f.sent, f.bytes.size() - f.sent, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n > 0) {
      f.sent += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
    EndFlushing(fd, false);
    return;
  }
  EndFlushing(fd, true);
}

void ConnectionGate::EndFlushing(int fd, bool ok) {
  auto it = flushing_.find(fd);
  if (it == flushing_.end()) return;
  const Flushing f = std::move(it->second);
  flushing_.erase(it);
  output_budget_.Give(f.bytes.size());
  epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
  if (!ok) {
    ResetAndClose(fd);
  } else if (f.close_after || f.requests_left <= 0) {
    ::shutdown(fd, SHUT_RDWR);
    close(fd);
  } else {
    Wait(fd, f.requests_left, true);
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
           Status::DeadlineExceeded("the request head (through its blank line) must arrive "
                                    "within the head timeout",
                                    "", ms, ms));
  }
  // Bodies read here that fall behind the minimum rate past the grace, or
  // pass the longest time any body may take: 408. Responses sent from here
  // past their time: reset.
  for (auto it = reading_.begin(); it != reading_.end();) {
    const Reading& r = it->second;
    const double t = Seconds(now - r.since);
    const double paced = options_.min_bytes_per_s * (t - Seconds(options_.transfer_grace));
    if (paced <= static_cast<double>(r.bytes.size() - r.head) &&
        t <= Seconds(options_.max_body_time)) {
      ++it;
      continue;
    }
    const int fd = it->first;
    auto next = std::next(it);
    EndReading(it);
    it = next;
    epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
    {
      std::lock_guard lock(mutex_);
      ++stats_.slow_body;
    }
    Refuse(fd, 408,
           Status::DeadlineExceeded(
               "the request body came slower than the server's minimum rate of " +
                   std::to_string(static_cast<long long>(options_.min_bytes_per_s)) +
                   " bytes/s (after a grace of " +
                   std::to_string(static_cast<long long>(Seconds(options_.transfer_grace))) +
                   " s, and at most " +
                   std::to_string(static_cast<long long>(Seconds(options_.max_body_time))) +
                   " s in all)",
               "body", Seconds(options_.max_body_time) * 1000.0, t * 1000.0));
  }
  std::vector<int> late;
  for (const auto& [fd, f] : flushing_) {
    if (now >= f.deadline) late.push_back(fd);
  }
  for (int fd : late) {
    {
      std::lock_guard lock(mutex_);
      ++stats_.slow_response;
    }
    EndFlushing(fd, false);
  }
  using Phase = Served::Phase;
  for (const auto& s : served) {
    std::lock_guard lock(s->mutex);
    if (s->shut || s->fd < 0) continue;
    if (s->phase == Phase::kHandling && !s->cancel.raised()) {
      // The client hung up (or half-closed, as nginx reads it) while its
      // request is handled: nobody waits for the answer.
      pollfd p{s->fd, POLLRDHUP, 0};
      if (poll(&p, 1, 0) == 1 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0) {
        s->cancel.Raise();
        std::lock_guard stats_lock(mutex_);
        ++stats_.cancelled;
      }
      continue;
    }
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

void ConnectionGate::OnWaiting(int fd) {
  const Inspection in = Inspect(fd);
  int requests_left = 0;
  {
    std::lock_guard lock(mutex_);
    auto it = waiting_.find(fd);
    if (it == waiting_.end()) return;  // timed out already
    if (in.seen > 0) it->second.started = true;
    if (in.verdict == Verdict::kWait) return;
    requests_left = it->second.requests_left;
    waiting_.erase(it);
    switch (in.verdict) {
      case Verdict::kTooLarge:
        ++stats_.head_too_large;
        break;
      case Verdict::kMalformed:
        ++(in.body_not_allowed ? stats_.body_not_allowed : stats_.malformed_head);
        break;
      case Verdict::kClosed:
        ++stats_.closed_early;
        break;
      case Verdict::kPass:
        ++stats_.passed;
        break;
      case Verdict::kProbe:
        ++stats_.probes;
        break;
      default:
        break;
    }
  }
  if (in.verdict == Verdict::kBody) {
    StartReading(fd, in, requests_left);  // stays in epoll, read from here
    return;
  }
  epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
  switch (in.verdict) {
    case Verdict::kPass:
      pool_->enqueue(
          [this, fd, requests_left] { ServeOnWorker(fd, requests_left, std::string(), false); });
      break;
    case Verdict::kProbe:
      probe_pool_->enqueue([this, fd] { ServeOnWorker(fd, 1, std::string(), true); });
      break;
    case Verdict::kTooLarge:
      Refuse(fd, 431,
             Status::LimitExceeded("the request head is too large", "",
                                   static_cast<double>(options_.max_head_bytes),
                                   static_cast<double>(in.seen)));
      break;
    case Verdict::kMalformed:
      Refuse(fd, in.rejection->http_status, in.rejection->status);
      break;
    default:
      close(fd);
      break;
  }
}

void ConnectionGate::Loop() {
  constexpr int kMaxEvents = 64;
  epoll_event events[kMaxEvents];
  auto next_check = Clock::now();
  while (!stopping_.load()) {
    const int n = epoll_wait(epoll_fd_, events, kMaxEvents, 100);
    std::vector<std::pair<int, Pending>> admitted;
    std::vector<std::pair<int, Flushing>> handed;
    {
      std::lock_guard lock(mutex_);
      admitted.swap(admitted_);
      handed.swap(handed_over_);
      for (const auto& [fd, pending] : admitted) waiting_.emplace(fd, pending);
    }
    EvictLongestWaiting();
    for (const auto& [fd, pending] : admitted) {
      epoll_event ev{};
      ev.events = EPOLLIN | EPOLLRDHUP | EPOLLET;  // each arrival, though unread
      ev.data.fd = fd;
      epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, fd, &ev);  // reports bytes already there
    }
    for (auto& [fd, flushing] : handed) {
      flushing_.emplace(fd, std::move(flushing));
      Watch(fd, EPOLLOUT);
      OnFlushing(fd);
    }
    for (int k = 0; k < n; ++k) {
      const int fd = events[k].data.fd;
      if (fd == wake_fd_) {
        uint64_t count;
        [[maybe_unused]] auto r = read(wake_fd_, &count, sizeof count);
        continue;
      }
      if (reading_.count(fd) != 0) {
        OnReading(fd);
      } else if (flushing_.count(fd) != 0) {
        OnFlushing(fd);
      } else {
        OnWaiting(fd);
      }
    }
    const auto now = Clock::now();
    if (now >= next_check) {
      CheckDeadlines(now);
      next_check = now + std::chrono::milliseconds(100);
      std::lock_guard lock(mutex_);
      stats_.reading = reading_.size();
      stats_.flushing = flushing_.size();
      stats_.body_buffer_bytes = reading_bytes_;
    }
  }
}

}  // namespace surfdeform::http
