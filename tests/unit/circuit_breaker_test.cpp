// The shared tier's circuit breaker, on a clock the test moves.
#include "service/circuit_breaker.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace surfdeform {
namespace {

using State = CircuitBreaker::State;

struct Fixture {
  CircuitBreaker::Clock::time_point now{};
  std::vector<State> changes;
  CircuitBreaker breaker{
      {3, 1000}, [this](State s) { changes.push_back(s); }, [this] { return now; }};
  void Advance(int ms) { now += std::chrono::milliseconds(ms); }
};

TEST(CircuitBreaker, OpensAfterConsecutiveFailuresOnly) {
  Fixture f;
  f.breaker.Failed();
  f.breaker.Failed();
  f.breaker.Succeeded();  // resets the run
  f.breaker.Failed();
  f.breaker.Failed();
  EXPECT_TRUE(f.breaker.Allow());
  EXPECT_TRUE(f.changes.empty());
  f.breaker.Failed();
  EXPECT_EQ(f.breaker.state(), State::kOpen);
  EXPECT_FALSE(f.breaker.Allow());
  EXPECT_EQ(f.changes, std::vector<State>{State::kOpen});
}

TEST(CircuitBreaker, OneProbeAfterTheCoolDownClosesOrReopensIt) {
  Fixture f;
  for (int k = 0; k < 3; ++k) f.breaker.Failed();
  f.Advance(999);
  EXPECT_FALSE(f.breaker.Allow());
  f.Advance(1);
  EXPECT_TRUE(f.breaker.Allow());   // the probe
  EXPECT_FALSE(f.breaker.Allow());  // only one at a time
  f.breaker.Failed();               // the probe failed: open for another second
  EXPECT_EQ(f.breaker.state(), State::kOpen);
  f.Advance(500);
  EXPECT_FALSE(f.breaker.Allow());
  f.Advance(500);
  EXPECT_TRUE(f.breaker.Allow());
  f.breaker.Succeeded();
  EXPECT_EQ(f.breaker.state(), State::kClosed);
  EXPECT_TRUE(f.breaker.Allow());
  EXPECT_EQ(f.changes, (std::vector<State>{State::kOpen, State::kHalfOpen, State::kOpen,
                                           State::kHalfOpen, State::kClosed}));
}

}  // namespace
}  // namespace surfdeform
