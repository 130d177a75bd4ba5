// The listening server: httplib's, with its accepted connections handed to
// the connection gate, and its backlog widened.
#pragma once

#include <httplib.h>
#include <sys/socket.h>

#include <atomic>

#include "http/connection_gate.hpp"
#include "service/metrics.hpp"

namespace surfdeform::http {

// httplib::Server with access to its listening socket, whose backlog httplib
// 0.11.4 fixes at 5: a burst of connections (a load test, 50 browser tabs)
// would overflow it. Accepted connections go through the connection gate
// (its task queue) before a worker serves them.
class Listener : public httplib::Server {
 public:
  void WidenBacklog(int backlog) {
    const auto fd = svr_sock_.load();
    if (fd != INVALID_SOCKET) ::listen(fd, backlog);  // Linux: updates the backlog
  }
  // The task queue of each listen(): the gate, whose workers serve.
  void UseGate(GateOptions options) {
    new_task_queue = [this, options] {
      auto* gate = new ConnectionGate(
          options, [this](httplib::Stream& stream, bool close_connection, bool& closed) {
            return process_request(stream, close_connection, closed, nullptr);
          });
      gate_.store(gate);
      return gate;
    };
  }
  // One request from `stream`, as on a connection (see HttpServer::ServeBytes).
  bool ServeStream(httplib::Stream& stream, bool& connection_closed) {
    return process_request(stream, false, connection_closed, nullptr);
  }
  ConnectionStats connection_stats() const {
    ConnectionGate* gate = gate_.load();
    return gate != nullptr ? gate->stats() : ConnectionStats{};
  }

 private:
  // httplib's accept loop calls this (through the gate's enqueue) for each
  // accepted socket: the gate holds it until its head is in.
  bool process_and_close_socket(socket_t sock) override {
    gate_.load()->Admit(sock);
    return true;
  }

  std::atomic<ConnectionGate*> gate_{nullptr};
};

}  // namespace surfdeform::http
