// draco_only_server: the ceiling of capacity_bench. An HTTP server that does
// the least any deformation server must do per request: read the request
// body, encode the answer with Draco (the service's output mesh, fixed, with
// the service's settings: DracoPeer), and send it. It deforms nothing. Its
// throughput under the same load generator, on the same cores, is what a
// surfdeform server whose own work cost nothing could reach; what is left
// between that and cores / Draco's encode time is the machine's (the load
// generator's CPU, loopback transfer, cores slowing each other) and not the
// server's.
//
// Usage: draco_only_server --ply FILE. Prints {"port":N} on its first line
// (as surfdeform-server does) and serves POST /v1/deform on 127.0.0.1 until
// SIGTERM. Same allocator settings, TCP_NODELAY and keep-alive as the
// service, and like it one encoding per core at a time (a pool of encoders,
// built before it serves): more requests wait.
#include <httplib.h>

#include <CLI/CLI.hpp>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "draco_peer.hpp"
#include "harness.hpp"
#include "service/allocator_tuning.hpp"

int main(int argc, char** argv) {
  CLI::App app{"An HTTP server that only reads the body and encodes a fixed mesh with Draco."};
  std::string ply_path;
  app.add_option("--ply", ply_path, "the mesh to encode, as the service's PLY output")
      ->required()
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);
  surfdeform::TuneAllocatorForServing();

  const std::string ply = surfdeform::bench::ReadFile(ply_path);
  using surfdeform::bench::DracoPeer;
  std::vector<std::unique_ptr<DracoPeer>> free_peers;
  for (unsigned k = 0; k < std::max(1u, std::thread::hardware_concurrency()); ++k) {
    free_peers.push_back(std::make_unique<DracoPeer>(ply));
    if (!free_peers.back()->ok()) {
      std::fprintf(stderr, "Draco could not read %s\n", ply_path.c_str());
      return 1;
    }
  }
  std::mutex mutex;
  std::condition_variable freed;

  httplib::Server server;
  server.set_tcp_nodelay(true);
  server.set_payload_max_length(64u << 20);
  server.Post("/v1/deform", [&](const httplib::Request&, httplib::Response& res) {
    std::unique_ptr<DracoPeer> peer;
    {
      std::unique_lock lock(mutex);
      freed.wait(lock, [&] { return !free_peers.empty(); });
      peer = std::move(free_peers.back());
      free_peers.pop_back();
    }
    std::string drc;
    const bool ok = peer->Encode(&drc);
    {
      std::lock_guard lock(mutex);
      free_peers.push_back(std::move(peer));
    }
    freed.notify_one();
    if (!ok) {
      res.status = 500;
      return;
    }
    res.set_content(std::move(drc), "application/octet-stream");
  });
  const int port = server.bind_to_any_port("127.0.0.1");
  if (port <= 0) return 1;
  std::printf("{\"port\":%d}\n", port);
  std::fflush(stdout);
  return server.listen_after_bind() ? 0 : 1;
}
