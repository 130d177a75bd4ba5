// A real redis-server (Debian's) on a free loopback port for a test: started,
// killed and restarted on the same port, and commands sent to it directly
// (to plant a corrupt value, fill it, or make it slow).
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "service/shared_tier.hpp"

namespace surfdeform::testing {

class RedisProcess {
 public:
  RedisProcess();  // started; port() is 0 if that failed
  ~RedisProcess();
  RedisProcess(const RedisProcess&) = delete;
  RedisProcess& operator=(const RedisProcess&) = delete;

  int port() const { return port_; }
  std::string url() const { return "redis://127.0.0.1:" + std::to_string(port_); }
  bool Start();  // on the same port; waits until it answers PING
  void Kill();   // SIGKILL, and waits

  // One command; its reply as text (strings, status, errors as "ERR ...",
  // integers in decimal, nil as "(nil)"), or "(no reply)".
  std::string Command(const std::vector<std::string>& argv);

 private:
  pid_t pid_ = -1;
  int port_ = 0;
};

// A shared tier on `url` with a short timeout (a test's), or null (and a
// test failure) for a URL it refuses.
std::shared_ptr<SharedTier> SharedTierAt(const std::string& url);

// A loopback TCP port that nothing listens on now.
int FreePort();

}  // namespace surfdeform::testing
