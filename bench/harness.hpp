// What every benchmark here needs: a file's bytes, medians of repeated
// timings. Benchmarks report medians (the machines are shared and noisy:
// one slow run must not move the figure) and ratios to a peer measured in
// the same run.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace surfdeform::bench {

// The whole file; exits with a message when it cannot be read (a benchmark
// without its input measures nothing).
std::string ReadFile(const std::string& path);

// The median (the upper one of an even count); 0 for none.
double Median(std::vector<double> values);

// Milliseconds since `t0` on the steady clock.
inline double MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The median wall time of `repeat` runs of `f`, in milliseconds.
template <typename F>
double MedianMs(int repeat, F&& f) {
  std::vector<double> times;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    times.push_back(MsSince(t0));
  }
  return Median(std::move(times));
}

}  // namespace surfdeform::bench
