// edit_request_bench: a live edit as the viewer sends it, once per pointer
// move of a control-point drag: POST /v1/surfaces?field=64 with the previous
// edit's id as "warm_start", gzip accepted, over loopback HTTP to the real
// server (in process, on a free port). Figure 10 at 16 x 16, control point 5
// raised by 1% of the patch per edit. Per edit (medians): the request end
// to end, and the server's own phases (Server-Timing), side by side with the
// flattening alone (the engine's part) and with zlib's default-level gzip of
// the same reply (what httplib would have spent on it).
#include <httplib.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness.hpp"
#include "loopback_server.hpp"
#include "service/allocator_tuning.hpp"
#include "service/content_coding.hpp"

using Clock = std::chrono::steady_clock;
using nlohmann::json;

using surfdeform::bench::Phase;

namespace {

// The time zlib's default level takes to gzip `bytes`, in ms.
double DefaultGzipMs(const std::string& bytes) {
  const auto t0 = Clock::now();
  const std::string packed = surfdeform::Gzip(bytes, -1);
  return packed.empty() ? 0.0 : surfdeform::bench::MsSince(t0);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"edit_request_bench: a live edit's request, end to end, against its flattening"};
  int edits = 30, field = 64;
  app.add_option("--edits", edits, "edits (requests)")->capture_default_str();
  app.add_option("--field", field, "the field's side (the viewer asks for 64)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  surfdeform::TuneAllocatorForServing();  // as surfdeform-server does

  surfdeform::ServiceOptions options;
  surfdeform::bench::LoopbackServer server(options);
  if (!server.ok()) return 1;
  httplib::Client client("127.0.0.1", server.port());
  client.set_read_timeout(60, 0);
  client.set_keep_alive(true);
  client.set_tcp_nodelay(true);
  client.set_decompress(false);  // as the bytes come; inflated below, outside the timing

  json figure10 =
      json::parse(surfdeform::bench::ReadFile(std::string(SURFDEFORM_DATA_DIR) + "/figure10.json"));
  figure10.erase("description");
  json request = {{"surface", figure10}, {"sampling", {{"nu", 16}, {"nv", 16}}}};
  const std::string path = "/v1/surfaces?field=" + std::to_string(field);
  const httplib::Headers gzip = {{"Accept-Encoding", "gzip, deflate, br"}};
  auto first = client.Post(path, gzip, request.dump(), "application/json");
  if (!first || first->status >= 300) return 1;
  std::string from;
  {
    httplib::Client plain("127.0.0.1", server.port());
    auto r = plain.Post("/v1/surfaces", request.dump(), "application/json");
    if (!r || r->status >= 300) return 1;
    from = json::parse(r->body).at("id");
  }
  std::vector<double> e2e, total, flatten, field_ms, gzip_default;
  size_t wire = 0, text = 0;
  for (int e = 1; e <= edits; ++e) {
    request["surface"]["control_points"][5][2] =
        figure10["control_points"][5][2].get<double>() + 0.1 * e;
    request["warm_start"] = from;
    const std::string body = request.dump();
    const auto t0 = Clock::now();
    auto r = client.Post(path, gzip, body, "application/json");
    e2e.push_back(surfdeform::bench::MsSince(t0));
    if (!r || r->status >= 300) return 1;
    const std::string timing = r->get_header_value("Server-Timing");
    total.push_back(Phase(timing, "total"));
    flatten.push_back(Phase(timing, "flatten"));
    field_ms.push_back(Phase(timing, "field"));
    wire = r->body.size();
    // The reply as text (the same request again, identity), for its id and
    // for the peer's gzip of the same bytes.
    httplib::Client plain("127.0.0.1", server.port());
    auto t = plain.Post(path, body, "application/json");
    if (!t || t->status >= 300) return 1;
    text = t->body.size();
    gzip_default.push_back(DefaultGzipMs(t->body));
    from = json::parse(t->body).at("id");
  }
  using surfdeform::bench::Median;
  const double m_e2e = Median(e2e), m_flatten = Median(flatten);
  std::printf("live edit: Figure 10 16x16, field %d, %d edits (medians, ms)\n", field, edits);
  std::printf("%10s %10s %10s %10s %12s %12s %10s %10s\n", "e2e", "server", "flatten", "field",
              "e2e/flatten", "zlib-6 gzip", "text KB", "wire KB");
  std::printf("%10.2f %10.2f %10.2f %10.2f %12.2f %12.2f %10.1f %10.1f\n", m_e2e, Median(total),
              m_flatten, Median(field_ms), m_e2e / m_flatten, Median(gzip_default),
              static_cast<double>(text) / 1024.0, static_cast<double>(wire) / 1024.0);
  return 0;
}
