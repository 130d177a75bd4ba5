// fork_join_bench: how soon the helper thread of a two-way fork starts
// working, after the process sat idle for a while (as a server does between
// requests), with the engine's ParallelChunks (which starts helpers on another
// CPU than the caller's) side by side with plain std::thread in the same run.
// A fork "ran serially" when its helper started only after the caller had
// finished its own half.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "engine/common/elapsed.hpp"
#include "engine/common/parallel.hpp"

using Clock = std::chrono::steady_clock;
using surfdeform::MsSince;

namespace {

// Busy work for `ms` milliseconds (a chunk of a data-parallel pass).
void Spin(double ms) {
  const auto t0 = Clock::now();
  std::atomic<double> sink{0.0};
  while (MsSince(t0) < ms) sink = sink + 1.0;
}

struct Outcome {
  double median_start_ms;
  int serial;
};

template <typename Fork>
Outcome Measure(int forks, int gap_ms, double work_ms, const Fork& fork) {
  std::vector<double> starts;
  int serial = 0;
  for (int k = 0; k < forks; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(gap_ms));
    const double start = fork(work_ms);
    starts.push_back(start);
    if (start >= 0.9 * work_ms) ++serial;
  }
  std::sort(starts.begin(), starts.end());
  return {starts[starts.size() / 2], serial};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Fork-join start latency: ParallelChunks vs plain std::thread."};
  int forks = 40;
  double work_ms = 2.0;
  app.add_option("--forks", forks, "forks per idle gap")->capture_default_str();
  app.add_option("--work-ms", work_ms, "each thread's share of a fork")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  // Returns when the helper (chunk 0) started, ms after the fork began.
  auto engine = [](double ms) {
    const auto t0 = Clock::now();
    double helper_start = 0.0;
    surfdeform::ParallelChunks(2, 2, [&](int chunk, int, int) {
      if (chunk == 0) helper_start = MsSince(t0);
      Spin(ms);
    });
    return helper_start;
  };
  auto plain = [](double ms) {
    const auto t0 = Clock::now();
    double helper_start = 0.0;
    std::thread helper([&] {
      helper_start = MsSince(t0);
      Spin(ms);
    });
    Spin(ms);
    helper.join();
    return helper_start;
  };
  std::printf("%u CPUs; %d forks per gap, %.1f ms of work per thread\n\n",
              std::thread::hardware_concurrency(), forks, work_ms);
  std::printf("%-8s | %-28s | %-28s\n", "idle gap", "ParallelChunks", "plain std::thread");
  std::printf("%-8s | %13s %14s | %13s %14s\n", "", "median start", "ran serially", "median start",
              "ran serially");
  for (int gap : {0, 5, 20}) {
    const Outcome a = Measure(forks, gap, work_ms, engine);
    const Outcome b = Measure(forks, gap, work_ms, plain);
    std::printf("%5d ms | %10.3f ms %8d / %-3d | %10.3f ms %8d / %-3d\n", gap, a.median_start_ms,
                a.serial, forks, b.median_start_ms, b.serial, forks);
  }
  return 0;
}
