// Admission control: slots, a FIFO queue with a time limit, refusals, the
// threads a request may use, and Retry-After from the measured service time.
#include "service/admission.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

namespace surfdeform {
namespace {

using namespace std::chrono_literals;

AdmissionOptions Options(int slots, int queue, double timeout_ms = 60000, int cores = 4) {
  return AdmissionOptions{slots, queue, timeout_ms, cores};
}

// Waits (bounded) until `admission` has `n` requests queued.
bool WaitQueued(const Admission& admission, int n) {
  for (int k = 0; k < 2000; ++k) {
    if (admission.stats().queued == n) return true;
    std::this_thread::sleep_for(1ms);
  }
  return false;
}

TEST(Admission, PastTheSlotsRequestsWaitAndPastTheQueueTheyAreRefused) {
  Admission admission(Options(1, 1));
  auto first = admission.Enter();
  ASSERT_TRUE(first.ok());
  EXPECT_FALSE(admission.Full());
  std::atomic<bool> second_in{false};
  std::thread second([&] {
    auto t = admission.Enter();
    second_in = t.ok();
  });
  ASSERT_TRUE(WaitQueued(admission, 1));
  EXPECT_TRUE(admission.Full());
  auto third = admission.Enter();  // the queue is full: refused at once
  ASSERT_FALSE(third.ok());
  EXPECT_EQ(third.status().code(), ErrorCode::kUnavailable);
  EXPECT_FALSE(second_in);
  { auto released = std::move(*first); }  // the slot goes to the waiter
  second.join();
  EXPECT_TRUE(second_in);
  const AdmissionStats s = admission.stats();
  EXPECT_EQ(s.admitted, 2u);
  EXPECT_EQ(s.waited, 1u);
  EXPECT_EQ(s.refused_full, 1u);
  EXPECT_EQ(s.running, 0);
}

TEST(Admission, WaitersAreAdmittedInArrivalOrder) {
  Admission admission(Options(1, 8));
  auto first = admission.Enter();
  ASSERT_TRUE(first.ok());
  std::optional<Admission::Ticket> holder(std::move(*first));
  std::vector<int> order;
  std::mutex order_mutex;
  std::vector<std::thread> waiters;
  for (int k = 0; k < 5; ++k) {
    waiters.emplace_back([&, k] {
      auto t = admission.Enter();
      ASSERT_TRUE(t.ok());
      std::lock_guard lock(order_mutex);
      order.push_back(k);
    });
    ASSERT_TRUE(WaitQueued(admission, k + 1));  // k is queued before k + 1 arrives
  }
  holder.reset();
  for (auto& w : waiters) w.join();
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(Admission, AWaitPastTheQueueTimeoutIsRefused) {
  Admission admission(Options(1, 4, /*timeout_ms=*/50));
  auto holder = admission.Enter();
  ASSERT_TRUE(holder.ok());
  const auto t0 = std::chrono::steady_clock::now();
  auto late = admission.Enter();
  const auto waited = std::chrono::steady_clock::now() - t0;
  ASSERT_FALSE(late.ok());
  EXPECT_EQ(late.status().code(), ErrorCode::kUnavailable);
  EXPECT_GE(waited, 45ms);
  EXPECT_LT(waited, 5s);
  // A caller's own bound, shorter than the timeout, wins.
  auto shorter = admission.Enter(/*max_wait_ms=*/1);
  EXPECT_FALSE(shorter.ok());
  EXPECT_EQ(admission.stats().refused_timeout, 2u);
  EXPECT_EQ(admission.stats().queued, 0);
}

TEST(Admission, ARequestAloneGetsEveryCoreUnderLoadOne) {
  Admission admission(Options(4, 0, 1000, /*cores=*/3));
  auto a = admission.Enter();
  EXPECT_EQ(a->threads(), 3);
  auto b = admission.Enter();
  EXPECT_EQ(b->threads(), 2);
  auto c = admission.Enter();
  EXPECT_EQ(c->threads(), 1);
  auto d = admission.Enter();
  EXPECT_EQ(d->threads(), 1);
}

TEST(Admission, RetryAfterFollowsTheMeasuredServiceTimeAndTheQueue) {
  Admission admission(Options(1, 64));
  EXPECT_EQ(admission.RetryAfterSeconds(), 1);  // nothing measured: the minimum
  {
    auto t = admission.Enter();
    std::this_thread::sleep_for(300ms);
  }
  const double service_s = admission.stats().service_ms_ewma / 1000;
  EXPECT_GE(service_s, 0.29);
  EXPECT_LT(service_s, 5);
  // One running, 20 queued: ~20.5 service times (>= 6 s) before a new one runs.
  auto running = admission.Enter();
  std::vector<std::thread> waiters;
  for (int k = 0; k < 20; ++k) waiters.emplace_back([&] { auto t = admission.Enter(); });
  ASSERT_TRUE(WaitQueued(admission, 20));
  const int retry = admission.RetryAfterSeconds();
  EXPECT_GE(retry, static_cast<int>(20.5 * 0.29));
  EXPECT_LE(retry, static_cast<int>(std::ceil(20.5 * service_s)) + 1);
  { auto released = std::move(*running); }
  for (auto& w : waiters) w.join();
}

}  // namespace
}  // namespace surfdeform
