#include "server_process.hpp"

#include <httplib.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>

namespace surfdeform::testing {

const char* ServerBinary() { return SURFDEFORM_SERVER_BINARY; }
const char* FaultServerBinary() { return SURFDEFORM_FAULT_SERVER_BINARY; }

ServerProcess::ServerProcess(const std::vector<std::string>& args)
    : ServerProcess(ServerBinary(), args) {}

ServerProcess::ServerProcess(const std::string& binary, const std::vector<std::string>& args) {
  // A server that refuses a body closes the connection while the client may
  // still be sending it: that must be an error return, not a fatal signal.
  signal(SIGPIPE, SIG_IGN);
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) return;
  std::vector<std::string> argv_strings = {binary, "--host", "127.0.0.1", "--port", "0"};
  // Uploads in memory only, unless the test asks for the disk store: the
  // user's data directory is not the tests' to fill.
  if (std::find(args.begin(), args.end(), "--persist-uploads") == args.end()) {
    argv_strings.insert(argv_strings.end(), {"--persist-uploads", "false"});
  }
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  pid_ = fork();
  if (pid_ == 0) {
    dup2(pipe_fds[1], STDOUT_FILENO);
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    std::vector<char*> argv;
    for (std::string& s : argv_strings) argv.push_back(s.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(pipe_fds[1]);
  out_fd_ = pipe_fds[0];
  // Read until the "listening" line, then keep draining in the background.
  std::string first;
  char c;
  while (read(out_fd_, &c, 1) == 1 && c != '\n') first.push_back(c);
  const std::string key = "\"port\":";
  const size_t at = first.find(key);
  if (at != std::string::npos) port_ = std::atoi(first.c_str() + at + key.size());
  log_ = first + "\n";
  reader_ = std::thread([this] {
    char buf[4096];
    ssize_t n;
    while (true) {
      if (log_paused_) {  // Stop() resumes it before it waits for this thread
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        continue;
      }
      n = read(out_fd_, buf, sizeof buf);
      if (n <= 0) break;
      std::lock_guard lock(mutex_);
      log_.append(buf, static_cast<size_t>(n));
    }
  });
}

int ServerProcess::Stop(int signal) {
  if (pid_ <= 0) return -1;
  kill(pid_, signal);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  log_paused_ = false;
  if (reader_.joinable()) reader_.join();
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + WTERMSIG(status);
}

std::string ServerProcess::Log() {
  std::lock_guard lock(mutex_);
  return log_;
}

ServerProcess::~ServerProcess() {
  log_paused_ = false;
  if (pid_ > 0) Stop(SIGKILL);
  if (reader_.joinable()) reader_.join();
  if (out_fd_ >= 0) close(out_fd_);
}

bool SendAll(int fd, const std::string& bytes) {
  size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return false;
    sent += static_cast<size_t>(n);
  }
  return true;
}

int ConnectLoopback(int port, int receive_buffer) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  if (receive_buffer > 0) {
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
  }
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

double MetricValue(const std::string& text, const std::string& series) {
  const size_t at = text.find("\n" + series + " ");
  if (at == std::string::npos) return -1;
  return std::atof(text.c_str() + at + series.size() + 2);
}

double ScrapeMetric(int port, const std::string& series) {
  httplib::Client c("127.0.0.1", port);
  auto r = c.Get("/metrics");
  return r ? MetricValue(r->body, series) : -1;
}

}  // namespace surfdeform::testing
