// The shared helpers' failure report (support/expect_ok.hpp) in the tests:
// a failed step is a test failure carrying the status, and an ok one is not.
#include "support/expect_ok.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "base/status.hpp"
#include "engine/surface/surface_spec.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

std::unique_ptr<Surface> NegativeCylinder() {
  CylinderSpec c;
  c.radius = -1.0;
  return testing::MakeValid(c);
}

TEST(ExpectOk, AFailedStepFailsTheRunningTestWithItsStatus) {
  EXPECT_NONFATAL_FAILURE(
      testing::ExpectOk(Result<int>(Status(ErrorCode::kInvalidArgument, "boom", "radius"))),
      "boom");
  testing::ExpectOk(Result<int>(3));  // passes without a report
  // Through a helper: a surface that cannot be made.
  EXPECT_NONFATAL_FAILURE(NegativeCylinder(), "radius");
}

}  // namespace
}  // namespace surfdeform
