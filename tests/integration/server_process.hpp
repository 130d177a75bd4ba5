// Starts the real surfdeform-server binary on a free loopback port for a
// test, and stops it with a signal. Its stdout (the JSON log) is collected.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace surfdeform::testing {

class ServerProcess {
 public:
  // Starts the server with `--host 127.0.0.1 --port 0` plus `args` (and
  // `--persist-uploads false` unless they say otherwise), and waits for its
  // "listening" line. port() is 0 when it failed to start.
  explicit ServerProcess(const std::vector<std::string>& args = {});
  // The same with another build of the server (e.g. the fault-point one).
  ServerProcess(const std::string& binary, const std::vector<std::string>& args);
  ~ServerProcess();  // SIGKILL if still running

  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  // Sends `signal` and waits for the exit; returns the exit status (or
  // 128 + signal when killed by one).
  int Stop(int signal);
  std::string Log();  // what it printed so far
  // Stops (or resumes) reading the server's standard output: with it
  // paused, the pipe fills and the server's writes to it would block.
  void PauseLog(bool paused) { log_paused_ = paused; }

 private:
  pid_t pid_ = -1;
  int port_ = 0;
  int out_fd_ = -1;
  std::thread reader_;
  std::mutex mutex_;
  std::string log_;
  std::atomic<bool> log_paused_{false};
};

// A TCP connection to 127.0.0.1:port, or -1. A `receive_buffer` (bytes) is
// set before connecting, so that the advertised window stays that small.
int ConnectLoopback(int port, int receive_buffer = 0);
// Sends all of `bytes` (MSG_NOSIGNAL); false once the peer stops taking them.
bool SendAll(int fd, const std::string& bytes);

// A sample of /metrics text: `series` is a name, with its labels where it
// has them (`surfdeform_connections_closed_total{reason="idle"}`); -1 when
// absent.
double MetricValue(const std::string& text, const std::string& series);
// The same, read from the server's /metrics (-1 when it does not answer).
double ScrapeMetric(int port, const std::string& series);

// The server binary, and the one with fault points (set by CMake).
const char* ServerBinary();
const char* FaultServerBinary();

}  // namespace surfdeform::testing
