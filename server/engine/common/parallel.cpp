#include "engine/common/parallel.hpp"

#include <algorithm>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#include <unistd.h>
#endif

namespace surfdeform::parallel_detail {

#if defined(__linux__)
namespace {

// The CPUs this process may run on, in order: the main thread's mask, not the
// calling thread's (which would be a single CPU if it were a pinned helper);
// read once (a container's cpuset does not change under a running server).
const std::vector<int>& AllowedCpus() {
  static const std::vector<int> cpus = [] {
    std::vector<int> out;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(getpid(), sizeof set, &set) != 0) return out;
    for (int c = 0; c < CPU_SETSIZE; ++c) {
      if (CPU_ISSET(c, &set)) out.push_back(c);
    }
    return out;
  }();
  return cpus;
}

}  // namespace

void StartOffCallerCpu(std::thread& helper, int index) {
  const std::vector<int>& cpus = AllowedCpus();
  const int count = static_cast<int>(cpus.size());
  if (index + 1 >= count) return;  // not enough CPUs for each thread to have one
  const int caller = sched_getcpu();
  const auto at = std::find(cpus.begin(), cpus.end(), caller);
  if (at == cpus.end()) return;
  const int cpu = cpus[(static_cast<int>(at - cpus.begin()) + 1 + index) % count];
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  pthread_setaffinity_np(helper.native_handle(), sizeof set, &set);  // a hint: errors ignored
}

#else

void StartOffCallerCpu(std::thread&, int) {}

#endif

}  // namespace surfdeform::parallel_detail
