// service_bench: end-to-end latency of POST /v1/deform over loopback HTTP
// (the real server, in process, on a free port) for the thin plate and the
// bunny on a cached 16x16 Figure 10 surface, side by side in the same run with
// the time Draco's own encoder takes on the same output. The target:
// the service adds at most 30% on top of encoding.
#include <httplib.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "draco_peer.hpp"
#include "harness.hpp"
#include "loopback_server.hpp"
#include "service/allocator_tuning.hpp"

using Clock = std::chrono::steady_clock;
using nlohmann::json;

namespace {

using surfdeform::bench::Phase;
using surfdeform::bench::ReadFile;

std::string PlateObj() {
  std::string obj;
  for (int k = 0; k < 8; ++k) {
    char line[96];
    std::snprintf(line, sizeof line, "v %g %g %g\n", (k & 1) ? 2.0 : -2.0, (k & 2) ? 1.0 : -1.0,
                  (k & 4) ? 0.1 : -0.1);
    obj += line;
  }
  return obj + "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Service benchmark: POST /v1/deform end to end vs Draco's encoder."};
  int repeat = 25;
  app.add_option("--repeat", repeat, "requests per model (median)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  surfdeform::TuneAllocatorForServing();  // as surfdeform-server does

  surfdeform::ServiceOptions options;
  options.limits.answer_cache_bytes = 0;  // every request does its work
  surfdeform::bench::LoopbackServer server(options);
  if (!server.ok()) return 1;
  // The transport floor: a bare cpp-httplib server on loopback that answers a
  // POST of the same body with as many bytes as the service's reply.
  httplib::Server bare;
  bare.set_tcp_nodelay(true);  // as surfdeform-server does
  bare.Post("/echo", [](const httplib::Request& req, httplib::Response& res) {
    res.set_content(std::string(std::stoul(req.get_header_value("X-Reply-Bytes")), 'x'),
                    "application/octet-stream");
  });
  const int bare_port = bare.bind_to_any_port("127.0.0.1");
  std::thread bare_runner([&] { bare.listen_after_bind(); });
  httplib::Client bare_client("127.0.0.1", bare_port);
  bare_client.set_keep_alive(true);
  bare_client.set_tcp_nodelay(true);

  httplib::Client client("127.0.0.1", server.port());
  client.set_read_timeout(60, 0);
  client.set_keep_alive(true);
  client.set_tcp_nodelay(true);

  json figure10 = json::parse(ReadFile(std::string(SURFDEFORM_DATA_DIR) + "/figure10.json"));
  figure10.erase("description");
  const json surface = {{"surface", figure10}, {"sampling", {{"nu", 16}, {"nv", 16}}}};
  auto created = client.Post("/v1/surfaces", surface.dump(), "application/json");
  if (!created || created->status >= 300) return 1;
  const std::string id = json::parse(created->body).at("id");
  std::printf("surface: Figure 10 Bezier, 16x16, flattened once (%s)\n\n",
              created->get_header_value("Server-Timing").c_str());
  std::printf("%-11s %-8s %8s %9s | %8s %8s %8s %8s %8s | %8s | %9s %10s\n", "model", "subdiv",
              "vertices", "e2e ms", "parse", "deform", "subdiv", "encode", "other", "floor",
              "draco ms", "e2e/draco");

  struct Model {
    const char* name;
    std::string bytes;
  };
  const Model models[] = {{"thin plate", PlateObj()},
                          {"bunny", ReadFile(std::string(SURFDEFORM_DATA_DIR) + "/bunny.ply")}};
  for (const char* mode : {"off", "adaptive"})
    for (const Model& m : models) {
      const json base = {{"surface_id", id},
                         {"placement", {{"scale", "fit"}, {"anchor", "center"}}},
                         {"subdivision", {{"mode", mode}}}};
      const std::string params = base.dump();
      json as_ply = base;
      as_ply["output"] = {{"format", "ply"}};
      // The same deformation as PLY: the peer's input, in the same vertex order.
      auto ply = client.Post("/v1/deform", {{"X-Surfdeform-Params", as_ply.dump()}}, m.bytes,
                             "application/octet-stream");
      if (!ply || ply->status != 200) return 1;
      surfdeform::bench::DracoPeer peer(ply->body);
      if (!peer.ok()) return 1;
      // Request and peer alternate, so that the machine's drift hits both.
      std::vector<double> e2e, draco, parse, deform, subdivide, encode, floor;
      int vertices = 0;
      for (int k = 0; k < repeat + 2; ++k) {
        const auto t0 = Clock::now();
        auto r = client.Post("/v1/deform", {{"X-Surfdeform-Params", params}}, m.bytes,
                             "application/octet-stream");
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        if (!r || r->status != 200) {
          std::fprintf(stderr, "request failed: %s\n", r ? r->body.c_str() : "no response");
          return 1;
        }
        const double peer_ms = peer.EncodeMs();
        const auto tf = Clock::now();
        auto echo = bare_client.Post("/echo", {{"X-Reply-Bytes", std::to_string(r->body.size())}},
                                     m.bytes, "application/octet-stream");
        const double floor_ms =
            std::chrono::duration<double, std::milli>(Clock::now() - tf).count();
        if (!echo || echo->body.size() != r->body.size()) return 1;
        if (k < 2) continue;  // warm-up
        e2e.push_back(ms);
        floor.push_back(floor_ms);
        draco.push_back(peer_ms);
        const std::string timing = r->get_header_value("Server-Timing");
        parse.push_back(Phase(timing, "parse"));
        deform.push_back(Phase(timing, "deform"));
        subdivide.push_back(Phase(timing, "subdivide"));
        encode.push_back(Phase(timing, "encode"));
        vertices = json::parse(r->get_header_value("X-Surfdeform-Stats")).at("vertices");
      }
      auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
      };
      const double total = median(e2e);
      const double other =
          total - median(parse) - median(deform) - median(subdivide) - median(encode);
      std::printf("%-11s %-8s %8d %9.3f | %8.3f %8.3f %8.3f %8.3f %8.3f | %8.3f | %9.3f %9.2fx\n",
                  m.name, mode, vertices, total, median(parse), median(deform), median(subdivide),
                  median(encode), other, median(floor), median(draco), total / median(draco));
    }
  std::printf(
      "\ne2e: client-measured request time (loopback, keep-alive); parse/deform/encode: "
      "the server's Server-Timing; other: HTTP, multipart-free raw body, copies.\n"
      "floor: a bare cpp-httplib server on loopback answering the same body with as many "
      "bytes (the transport alone).\n"
      "draco ms: draco::Encoder on the decoded output, same settings (14 bits, speed 5).\n");
  bare.stop();
  bare_runner.join();
  return 0;
}
