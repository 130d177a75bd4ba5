// capacity_bench: the server's CPU time per request and its throughput under
// concurrency, side by side in the same run with Draco's own encoder on the
// same output at the same concurrency (the physical limit: a request cannot
// cost less than encoding its answer).
//
// The real surfdeform-server runs as a child process, so that its CPU time
// (/proc/PID/stat) is its own; k client threads (keep-alive, loopback) send
// POST /v1/deform with the raw mesh by the id of the cached Figure 10 surface,
// Draco out, for a fixed time. Then, with the server idle, k threads run
// draco::Encoder on the service's output mesh (read by Draco's PLY reader, in
// the service's vertex order) for the same time; this process's CPU time
// (getrusage) is theirs. Phases alternate, several rounds per step, so that
// the machine's drift hits both: on the 2-vCPU machine one vCPU ran ~30%
// slower than the other for minutes at a time (BENCHMARKS.md), which a
// single pair of phases caught on one side only. Rates and CPU times are
// totals over the rounds; the ratio is the median of the rounds' ratios; the
// limit uses Draco's fastest round.
//
// A third phase per round loads bench/draco_only_server the same way: a
// server that only reads the body and encodes the same output with Draco.
// Its throughput is the ceiling this machine and this load generator allow
// any server (the load generator's CPU and loopback transfer share the
// cores); "of ceiling" is the server's throughput against it at the same
// concurrency. Targets:
// server CPU per request at most 1.25x Draco's (subdivision off) and 1.35x (adaptive); throughput
// at the best concurrency at least 80% of cores / Draco's encode CPU time.
#include <httplib.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "draco_peer.hpp"
#include "harness.hpp"

using Clock = std::chrono::steady_clock;
using nlohmann::json;

namespace {

using surfdeform::bench::ReadFile;

// A server binary (args[0]) as a child that prints {"port":N} first; its CPU
// seconds from /proc.
class Child {
 public:
  explicit Child(std::vector<std::string> args) {
    int fds[2];
    if (pipe(fds) != 0) return;
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      close(fds[0]);
      close(fds[1]);
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(fds[1]);
    std::string line;
    char c;
    while (read(fds[0], &c, 1) == 1 && c != '\n') line.push_back(c);
    close(fds[0]);
    const size_t at = line.find("\"port\":");
    if (at != std::string::npos) port_ = std::atoi(line.c_str() + at + 7);
  }
  ~Child() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  int port() const { return port_; }
  double CpuSeconds() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/stat");
    std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::istringstream rest(stat.substr(stat.rfind(')') + 2));
    std::string field;
    unsigned long long utime = 0, stime = 0;
    for (int k = 3; k <= 15 && rest >> field; ++k) {
      if (k == 14) utime = std::stoull(field);
      if (k == 15) stime = std::stoull(field);
    }
    return static_cast<double>(utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
  }

 private:
  pid_t pid_ = -1;
  int port_ = 0;
};

// The machine's idle and total jiffies, all cores (/proc/stat's first line).
struct MachineTicks {
  unsigned long long idle = 0, total = 0;
};
MachineTicks ReadMachineTicks() {
  std::ifstream in("/proc/stat");
  std::string cpu;
  in >> cpu;
  MachineTicks t;
  unsigned long long v = 0;
  for (int k = 0; k < 8 && in >> v; ++k) {
    t.total += v;
    if (k == 3 || k == 4) t.idle += v;  // idle, iowait
  }
  return t;
}

double ProcessCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

struct Sample {
  double per_second = 0;  // requests (or encodes) per second
  double cpu_ms = 0;      // CPU time per request (or encode)
};

// One concurrency step: totals over its rounds.
struct Step {
  int k = 0;
  Sample server, draco, ceiling;
  double client_ms = 0;        // the load generator's CPU time per request
  double idle = 0;             // the machine's idle share during the server phases
  std::vector<double> ratios;  // server CPU per request / Draco's per encode, by round (sorted)
  double ratio = 0;            // their median
};

// k threads calling `once` (true: done one) for `seconds`.
template <class Once>
int RunFor(int k, double seconds, Once once) {
  std::atomic<int> done{0};
  std::atomic<bool> failed{false};
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(seconds));
  std::vector<std::thread> threads;
  for (int t = 0; t < k; ++t) {
    threads.emplace_back([&, t] {
      while (Clock::now() < end && !failed) {
        if (once(t)) {
          ++done;
        } else {
          failed = true;
        }
      }
    });
  }
  for (auto& th : threads) th.join();
  return failed ? -1 : done.load();
}

// --forms: the request forms side by side, each a server with
// no kept answers but the last. Per form and concurrency: requests per
// second, the server's CPU per request, bytes per answer, and the wall time
// of one request at one connection (median); then the ratios to inline
// Draco. Forms alternate within each round, so that the machine's drift
// hits them alike.
struct Form {
  const char* name;
  Child* server;
  std::string path_params;  // X-Surfdeform-Params (raw mesh body), or
  std::string json_body;    // the whole body (application/json: by model id)
  const char* accept;
};

struct FormStep {
  int served = 0;
  double cpu_s = 0.0, bytes = 0.0;
  std::vector<double> wall_ms;  // one connection: each request's
};

int RunForms(double seconds, int rounds, int max_concurrency, const std::string& model_path) {
  const std::string bunny = ReadFile(model_path);
  Child work({SURFDEFORM_SERVER_BINARY, "--host", "127.0.0.1", "--port", "0", "--log-level", "off",
              "--answer-cache-mib", "0"});
  Child kept(
      {SURFDEFORM_SERVER_BINARY, "--host", "127.0.0.1", "--port", "0", "--log-level", "off"});
  if (work.port() == 0 || kept.port() == 0) return 1;
  json figure10 = json::parse(ReadFile(std::string(SURFDEFORM_DATA_DIR) + "/figure10.json"));
  figure10.erase("description");
  const json surface = {{"surface", figure10}, {"sampling", {{"nu", 16}, {"nv", 16}}}};
  std::string surface_id, model_id;
  for (Child* c : {&work, &kept}) {
    httplib::Client setup("127.0.0.1", c->port());
    setup.set_read_timeout(60, 0);
    auto created = setup.Post("/v1/surfaces", surface.dump(), "application/json");
    auto uploaded = setup.Post("/v1/models", bunny, "application/octet-stream");
    if (!created || created->status >= 300 || !uploaded || uploaded->status >= 300) return 1;
    surface_id = json::parse(created->body).at("id");
    model_id = json::parse(uploaded->body).at("id");
  }
  const json base = {{"surface_id", surface_id},
                     {"placement", {{"scale", "fit"}, {"anchor", "center"}}},
                     {"subdivision", {{"mode", "off"}}}};
  json by_id = base;
  by_id["model_id"] = model_id;
  json by_id_meshopt = by_id;
  by_id_meshopt["output"] = {{"compression", "meshopt"}};
  std::vector<Form> forms = {
      {"inline Draco", &work, base.dump(), "", "application/octet-stream"},
      {"by id, Draco", &work, "", by_id.dump(), "application/octet-stream"},
      {"by id, meshopt", &work, "", by_id_meshopt.dump(), "model/gltf-binary"},
      {"repeated (kept)", &kept, "", by_id_meshopt.dump(), "model/gltf-binary"},
  };
  const size_t n = forms.size();
  std::vector<std::vector<std::unique_ptr<httplib::Client>>> clients(n);
  for (size_t f = 0; f < n; ++f) {
    for (int t = 0; t < max_concurrency; ++t) {
      auto c = std::make_unique<httplib::Client>("127.0.0.1", forms[f].server->port());
      c->set_keep_alive(true);
      c->set_tcp_nodelay(true);
      c->set_read_timeout(60, 0);
      clients[f].push_back(std::move(c));
    }
  }
  // One request of form f on connection t; its answer's size to *bytes.
  auto send = [&](size_t f, int t, size_t* bytes) {
    const Form& form = forms[f];
    httplib::Result r = form.json_body.empty()
                            ? clients[f][t]->Post("/v1/deform",
                                                  {{"X-Surfdeform-Params", form.path_params},
                                                   {"Accept", form.accept}},
                                                  bunny, "application/octet-stream")
                            : clients[f][t]->Post("/v1/deform", {{"Accept", form.accept}},
                                                  form.json_body, "application/json");
    if (!r || r->status != 200) return false;
    *bytes = r->body.size();
    return true;
  };
  for (size_t f = 0; f < n; ++f) {
    size_t bytes = 0;
    for (int warm = 0; warm < 4; ++warm) {
      if (!send(f, 0, &bytes)) {
        std::fprintf(stderr, "%s: the warm-up request failed\n", forms[f].name);
        return 1;
      }
    }
  }
  std::printf(
      "\nrequest forms: %s (%zu bytes) on Figure 10 (16x16), subdivision off; no "
      "kept answers but in the last form; %.1f s per form and round, %d rounds\n",
      model_path.c_str(), bunny.size(), seconds, rounds);
  std::printf("%-16s %5s | %9s %11s %10s %9s\n", "form", "conc", "req/s", "CPU ms/req", "bytes",
              "1-conn ms");
  std::vector<std::vector<FormStep>> steps(n, std::vector<FormStep>(max_concurrency + 1));
  for (int k = 1; k <= max_concurrency; ++k) {
    for (int round = 0; round < rounds; ++round) {
      for (size_t f = 0; f < n; ++f) {
        FormStep& s = steps[f][k];
        std::vector<std::vector<double>> walls(k);
        std::vector<double> sizes(k, 0.0);
        const double c0 = forms[f].server->CpuSeconds();
        const int served = RunFor(k, seconds, [&](int t) {
          size_t bytes = 0;
          const auto t0 = Clock::now();
          const bool ok = send(f, t, &bytes);
          walls[t].push_back(surfdeform::bench::MsSince(t0));
          sizes[t] = static_cast<double>(bytes);
          return ok;
        });
        const double c1 = forms[f].server->CpuSeconds();
        if (served <= 0) {
          std::fprintf(stderr, "%s failed at concurrency %d\n", forms[f].name, k);
          return 1;
        }
        s.served += served;
        s.cpu_s += c1 - c0;
        s.bytes = sizes[0];
        if (k == 1) s.wall_ms.insert(s.wall_ms.end(), walls[0].begin(), walls[0].end());
      }
    }
  }
  struct Best {
    double per_second = 0, cpu_ms = 0, bytes = 0, wall_ms = 0;
    int k = 0;
  };
  std::vector<Best> best(n);
  for (size_t f = 0; f < n; ++f) {
    for (int k = 1; k <= max_concurrency; ++k) {
      const FormStep& s = steps[f][k];
      const double per_second = s.served / (seconds * rounds);
      const double cpu_ms = 1000 * s.cpu_s / s.served;
      const double wall = k == 1 ? surfdeform::bench::Median(s.wall_ms) : 0.0;
      std::printf("%-16s %5d | %9.1f %11.2f %10.0f %9s\n", forms[f].name, k, per_second, cpu_ms,
                  s.bytes, k == 1 ? std::to_string(wall).substr(0, 6).c_str() : "");
      if (per_second > best[f].per_second) {
        best[f] = {per_second, cpu_ms, s.bytes, best[f].wall_ms, k};
      }
      if (k == 1) best[f].wall_ms = wall;
    }
  }
  std::printf("\n%-16s | %9s %5s %11s %10s %9s | %9s %9s %9s %9s\n", "form", "capacity", "at",
              "CPU ms/req", "bytes", "1-conn ms", "capacity", "CPU", "bytes", "1-conn");
  std::printf("%-16s | %9s %5s %11s %10s %9s | %39s\n", "", "req/s", "conc", "", "", "",
              "ratios to inline Draco");
  for (size_t f = 0; f < n; ++f) {
    const Best& b = best[f];
    std::printf("%-16s | %9.1f %5d %11.2f %10.0f %9.2f | %8.2fx %8.2fx %8.2fx %8.2fx\n",
                forms[f].name, b.per_second, b.k, b.cpu_ms, b.bytes, b.wall_ms,
                b.per_second / best[0].per_second, b.cpu_ms / best[0].cpu_ms,
                b.bytes / best[0].bytes, b.wall_ms / best[0].wall_ms);
  }
  std::printf(
      "targets: by id with meshopt >= 3x inline Draco's capacity (%.2fx); by id with "
      "Draco >= 1.1x (%.2fx); one request by id with meshopt at one connection <= 1/3 of inline "
      "Draco's wall time (%.2f)\n",
      best[2].per_second / best[0].per_second, best[1].per_second / best[0].per_second,
      best[2].wall_ms / best[0].wall_ms);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Capacity benchmark: server CPU per request and throughput vs Draco's encoder."};
  double seconds = 4;
  int max_concurrency = 4;
  int rounds = 3;
  app.add_option("--seconds", seconds, "time per step and phase")->capture_default_str();
  app.add_option("--rounds", rounds, "server and Draco phases, alternated, per step")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--max-concurrency", max_concurrency, "the last step")->capture_default_str();
  bool forms = false;
  std::string model = std::string(SURFDEFORM_DATA_DIR) + "/bunny.ply";
  app.add_option("--model", model, "with --forms: the mesh file")->capture_default_str();
  app.add_flag("--forms", forms,
               "compare the request forms instead (inline Draco, by model id with Draco and with "
               "meshopt, repeated answers kept)");
  CLI11_PARSE(app, argc, argv);
  if (forms) {
    return RunForms(seconds, rounds, max_concurrency, model);
  }
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

  // No kept answers: every request does its work.
  Child server({SURFDEFORM_SERVER_BINARY, "--host", "127.0.0.1", "--port", "0", "--log-level",
                "off", "--answer-cache-mib", "0"});
  if (server.port() == 0) {
    std::fprintf(stderr, "the server did not start (%s)\n", SURFDEFORM_SERVER_BINARY);
    return 1;
  }
  httplib::Client setup("127.0.0.1", server.port());
  setup.set_read_timeout(60, 0);
  json figure10 = json::parse(ReadFile(std::string(SURFDEFORM_DATA_DIR) + "/figure10.json"));
  figure10.erase("description");
  const json surface = {{"surface", figure10}, {"sampling", {{"nu", 16}, {"nv", 16}}}};
  auto created = setup.Post("/v1/surfaces", surface.dump(), "application/json");
  if (!created || created->status >= 300) return 1;
  const std::string id = json::parse(created->body).at("id");
  const std::string bunny = ReadFile(std::string(SURFDEFORM_DATA_DIR) + "/bunny.ply");
  std::printf(
      "bunny (%zu bytes) on the cached Figure 10 surface (16x16), Draco out; %d cores; "
      "%.1f s per phase, %d rounds of both phases per step\n",
      bunny.size(), cores, seconds, rounds);

  for (const char* mode : {"off", "adaptive"}) {
    const json base = {{"surface_id", id},
                       {"placement", {{"scale", "fit"}, {"anchor", "center"}}},
                       {"subdivision", {{"mode", mode}}}};
    json as_ply = base;
    as_ply["output"] = {{"format", "ply"}};
    auto ply = setup.Post("/v1/deform", {{"X-Surfdeform-Params", as_ply.dump()}}, bunny,
                          "application/octet-stream");
    if (!ply || ply->status != 200) return 1;
    char ply_path[] = "/tmp/capacity_bench_XXXXXX";
    const int ply_fd = mkstemp(ply_path);
    if (ply_fd < 0 || write(ply_fd, ply->body.data(), ply->body.size()) !=
                          static_cast<ssize_t>(ply->body.size())) {
      return 1;
    }
    close(ply_fd);
    Child ceiling({SURFDEFORM_DRACO_ONLY_SERVER_BINARY, "--ply", ply_path});
    unlink(ply_path);
    if (ceiling.port() == 0) {
      std::fprintf(stderr, "the Draco-only server did not start (%s)\n",
                   SURFDEFORM_DRACO_ONLY_SERVER_BINARY);
      return 1;
    }
    std::vector<std::unique_ptr<surfdeform::bench::DracoPeer>> peers;
    std::vector<std::unique_ptr<httplib::Client>> clients, ceiling_clients;
    auto client_of = [](int port) {
      auto c = std::make_unique<httplib::Client>("127.0.0.1", port);
      c->set_keep_alive(true);
      c->set_tcp_nodelay(true);
      c->set_read_timeout(60, 0);
      return c;
    };
    for (int t = 0; t < max_concurrency; ++t) {
      peers.push_back(std::make_unique<surfdeform::bench::DracoPeer>(ply->body));
      if (!peers.back()->ok()) return 1;
      clients.push_back(client_of(server.port()));
      ceiling_clients.push_back(client_of(ceiling.port()));
    }
    const std::string params = base.dump();
    for (int warm = 0; warm < 4; ++warm) {  // both servers' arenas and caches, as in use
      const auto a = clients[0]->Post("/v1/deform", {{"X-Surfdeform-Params", params}}, bunny,
                                      "application/octet-stream");
      const auto b = ceiling_clients[0]->Post("/v1/deform", bunny, "application/octet-stream");
      if (!a || a->status != 200 || !b || b->status != 200) return 1;
    }
    std::printf(
        "\nsubdivision %s\n%5s | %9s %11s %10s %5s | %9s %11s | %10s %11s | %9s %9s %11s | %s\n",
        mode, "conc", "server/s", "CPU ms/req", "client ms", "idle", "draco/s", "CPU ms/enc",
        "ceiling/s", "CPU ms/req", "CPU ratio", "of limit", "of ceiling", "rounds' ratios");
    // The physical limit: every core encoding, at the CPU time of Draco's
    // fastest round in this run (any step): a phase slowed by the machine
    // cannot lower the bar.
    double fastest_draco_ms = 1e300;
    std::vector<Step> steps;
    for (int k = 1; k <= max_concurrency; ++k) {
      Step step;
      step.k = k;
      int served = 0, encoded = 0, echoed = 0;
      double server_cpu = 0, draco_cpu = 0, ceiling_cpu = 0, client_cpu = 0, idle_ticks = 0,
             total_ticks = 0;
      for (int round = 0; round < rounds; ++round) {
        const double s0 = server.CpuSeconds();
        const double c0 = ProcessCpuSeconds();
        const MachineTicks m0 = ReadMachineTicks();
        const int n_served = RunFor(k, seconds, [&](int t) {
          auto r = clients[t]->Post("/v1/deform", {{"X-Surfdeform-Params", params}}, bunny,
                                    "application/octet-stream");
          return r && r->status == 200;
        });
        const double s1 = server.CpuSeconds();
        const double c1 = ProcessCpuSeconds();
        const MachineTicks m1 = ReadMachineTicks();
        if (n_served <= 0) {
          std::fprintf(stderr, "requests failed at concurrency %d\n", k);
          return 1;
        }
        const double p0 = ProcessCpuSeconds();
        const int n_encoded = RunFor(k, seconds, [&](int t) { return peers[t]->EncodeMs() > 0; });
        const double p1 = ProcessCpuSeconds();
        const double e0 = ceiling.CpuSeconds();
        const int n_echoed = RunFor(k, seconds, [&](int t) {
          auto r = ceiling_clients[t]->Post("/v1/deform", {{"X-Surfdeform-Params", params}}, bunny,
                                            "application/octet-stream");
          return r && r->status == 200;
        });
        const double e1 = ceiling.CpuSeconds();
        if (n_echoed <= 0) {
          std::fprintf(stderr, "the Draco-only server failed at concurrency %d\n", k);
          return 1;
        }
        echoed += n_echoed;
        ceiling_cpu += e1 - e0;
        const double draco_ms = 1000 * (p1 - p0) / std::max(n_encoded, 1);
        fastest_draco_ms = std::min(fastest_draco_ms, draco_ms);
        step.ratios.push_back(1000 * ((s1 - s0) / n_served) / draco_ms);
        served += n_served;
        encoded += n_encoded;
        server_cpu += s1 - s0;
        client_cpu += c1 - c0;
        idle_ticks += static_cast<double>(m1.idle - m0.idle);
        total_ticks += static_cast<double>(m1.total - m0.total);
        draco_cpu += p1 - p0;
      }
      std::sort(step.ratios.begin(), step.ratios.end());
      step.ratio = step.ratios[step.ratios.size() / 2];
      step.server = {served / (seconds * rounds), 1000 * server_cpu / served};
      step.draco = {encoded / (seconds * rounds), 1000 * draco_cpu / encoded};
      step.ceiling = {echoed / (seconds * rounds), 1000 * ceiling_cpu / echoed};
      step.client_ms = 1000 * client_cpu / served;
      step.idle = idle_ticks / std::max(total_ticks, 1.0);
      steps.push_back(std::move(step));
    }
    const double limit = cores * 1000.0 / fastest_draco_ms;
    const Step* best = &steps.front();
    const Step* best_ceiling = &steps.front();
    for (const Step& s : steps) {
      std::printf(
          "%5d | %9.1f %11.2f %10.2f %4.0f%% | %9.1f %11.2f | %10.1f %11.2f | %8.2fx %8.0f%% "
          "%10.0f%% | %.2f-%.2fx\n",
          s.k, s.server.per_second, s.server.cpu_ms, s.client_ms, 100 * s.idle, s.draco.per_second,
          s.draco.cpu_ms, s.ceiling.per_second, s.ceiling.cpu_ms, s.ratio,
          100 * s.server.per_second / limit, 100 * s.server.per_second / s.ceiling.per_second,
          s.ratios.front(), s.ratios.back());
      if (s.server.per_second > best->server.per_second) best = &s;
      if (s.ceiling.per_second > best_ceiling->ceiling.per_second) best_ceiling = &s;
    }
    std::printf(
        "best: %.1f req/s at %d (%.0f%% of cores / Draco's fastest encode CPU time, %.2f ms: "
        "%.1f/s; target 80%%); CPU per request %.2fx Draco's at that concurrency (target "
        "%.2fx)\n",
        best->server.per_second, best->k, 100 * best->server.per_second / limit, fastest_draco_ms,
        limit, best->ratio, std::string(mode) == "off" ? 1.25 : 1.35);
    std::printf(
        "ceiling: the Draco-only server's best, %.1f/s at %d, is %.0f%% of that limit; the "
        "server's best is %.0f%% of it\n",
        best_ceiling->ceiling.per_second, best_ceiling->k,
        100 * best_ceiling->ceiling.per_second / limit,
        100 * best->server.per_second / best_ceiling->ceiling.per_second);
  }
  std::printf(
      "\nCPU ratio: the server's CPU time per request / Draco's CPU time per encode, both at "
      "that concurrency (the median over the rounds; their range in the last column).\nof limit: "
      "server requests per second / (cores / Draco's CPU time "
      "per encode in its fastest round of the run, at any concurrency).\nceiling: "
      "bench/draco_only_server under the same load (reads the body, encodes the same output "
      "with Draco, sends it; deforms nothing); of ceiling: server requests per second / its, "
      "at that concurrency.\nclient ms: this process's "
      "CPU time per request while it "
      "loads the server (the load generator shares the cores); idle: the machine's idle share "
      "then (/proc/stat).\n");
  return 0;
}
