#include "redis_process.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <hiredis/hiredis.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

namespace surfdeform::testing {

int FreePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0) {
    port = ntohs(addr.sin_port);
  }
  close(fd);
  return port;
}

RedisProcess::RedisProcess() : port_(FreePort()) {
  if (!Start()) port_ = 0;
}

RedisProcess::~RedisProcess() { Kill(); }

bool RedisProcess::Start() {
  if (pid_ > 0) return true;
  const std::string port = std::to_string(port_);
  pid_ = fork();
  if (pid_ == 0) {
    execlp("redis-server", "redis-server", "--port", port.c_str(), "--bind", "127.0.0.1", "--save",
           "", "--appendonly", "no", "--loglevel", "warning", "--logfile", "/dev/null",
           "--enable-debug-command", "local", static_cast<char*>(nullptr));
    _exit(127);
  }
  for (int attempt = 0; attempt < 200; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (Command({"PING"}) == "PONG") return true;
  }
  return false;
}

void RedisProcess::Kill() {
  if (pid_ <= 0) return;
  kill(pid_, SIGKILL);
  waitpid(pid_, nullptr, 0);
  pid_ = -1;
}

std::string RedisProcess::Command(const std::vector<std::string>& argv) {
  redisContext* c = redisConnectWithTimeout("127.0.0.1", port_, timeval{1, 0});
  if (c == nullptr || c->err != 0) {
    if (c != nullptr) redisFree(c);
    return "(no reply)";
  }
  redisSetTimeout(c, timeval{5, 0});
  std::vector<const char*> args;
  std::vector<size_t> lengths;
  for (const std::string& a : argv) {
    args.push_back(a.data());
    lengths.push_back(a.size());
  }
  auto* r = static_cast<redisReply*>(
      redisCommandArgv(c, static_cast<int>(args.size()), args.data(), lengths.data()));
  std::string out = "(no reply)";
  if (r != nullptr) {
    switch (r->type) {
      case REDIS_REPLY_INTEGER:
        out = std::to_string(r->integer);
        break;
      case REDIS_REPLY_NIL:
        out = "(nil)";
        break;
      case REDIS_REPLY_ARRAY:
        out = "(array of " + std::to_string(r->elements) + ")";
        break;
      default:
        out.assign(r->str, r->len);
    }
    freeReplyObject(r);
  }
  redisFree(c);
  return out;
}

std::shared_ptr<SharedTier> SharedTierAt(const std::string& url) {
  SharedTierOptions o;
  o.url = url;
  o.timeout_ms = 200;
  auto tier = SharedTier::Create(o, nullptr);
  EXPECT_TRUE(tier.ok()) << tier.status().ToString();
  return tier.ok() ? std::shared_ptr<SharedTier>(std::move(*tier)) : nullptr;
}

}  // namespace surfdeform::testing
