// The server's malloc tuning bounds glibc's arenas: threads started after it
// share at most the given number. Each case runs in a fresh process (a death
// test, "threadsafe" style re-runs the binary), since arenas made by earlier
// tests' threads are never freed.
#include "service/allocator_tuning.hpp"

#include <gtest/gtest.h>
#include <malloc.h>

#include <cstdio>
#include <cstdlib>
#include <latch>
#include <string>
#include <thread>
#include <vector>

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define SURFDEFORM_SANITIZED_MALLOC 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SURFDEFORM_SANITIZED_MALLOC 1
#endif

namespace surfdeform {
namespace {

// The arenas glibc reports: one <heap nr="..."> element each.
int ArenasInUse() {
  char* text = nullptr;
  size_t size = 0;
  FILE* out = open_memstream(&text, &size);
  if (out == nullptr) return -1;
  malloc_info(0, out);
  std::fclose(out);
  const std::string xml(text, size);
  std::free(text);
  int count = 0;
  for (size_t at = xml.find("<heap nr="); at != std::string::npos;
       at = xml.find("<heap nr=", at + 1)) {
    ++count;
  }
  return count;
}

// `threads` threads each allocate a 1 MiB block (under the 32 MiB mmap
// threshold: from an arena) and hold it until all have theirs, so that no
// thread can take an arena another has left. A thread takes an arena at its
// first allocation: a new one while the limit allows, else a shared one.
void AllocateOnThreads(int threads) {
  std::latch all_hold(threads);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&all_hold] {
      std::vector<char> block(1u << 20, 1);
      all_hold.arrive_and_wait();
      if (block[block.size() / 2] != 1) std::abort();
    });
  }
  for (std::thread& th : pool) th.join();
}

// Exits with the number of arenas after eight allocating threads under the
// given limit (the exit code is the observable of a death test).
[[noreturn]] void CountArenasUnderLimit(int arenas) {
  TuneAllocatorForServing(32u << 20, 256u << 20, arenas);
  AllocateOnThreads(8);
  std::exit(ArenasInUse());
}

class AllocatorTuning : public ::testing::Test {
 protected:
  void SetUp() override {
#ifdef SURFDEFORM_SANITIZED_MALLOC
    GTEST_SKIP() << "the sanitizer replaces malloc: glibc's arenas are unused";
#endif
    GTEST_FLAG_SET(death_test_style, "threadsafe");
  }
};

TEST_F(AllocatorTuning, ThreadsShareAtMostTheGivenArenas) {
  EXPECT_EXIT(CountArenasUnderLimit(2), ::testing::ExitedWithCode(2), "");
}

// The control: with a limit above the threads, each thread made its own
// arena (the main one plus eight), so the count above is the limit's doing.
TEST_F(AllocatorTuning, WithoutALowLimitEachThreadMakesAnArena) {
  EXPECT_EXIT(CountArenasUnderLimit(64), ::testing::ExitedWithCode(9), "");
}

}  // namespace
}  // namespace surfdeform
