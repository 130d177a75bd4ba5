// The request prologue alone: admission and the threads it allows, the
// parameters' JSON, the mesh's import within the limits, the parse time and
// the clock.
#include "service/request_work.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace surfdeform {
namespace {

const char kTriangle[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST(RequestWork, AdmissionGivesTheTicketsThreadsWithinTheEngineLimit) {
  ServiceLimits limits;
  Admission admission({/*slots=*/1, /*queue=*/0, /*queue_timeout_ms=*/10, /*cores=*/4});
  {
    RequestWork work(limits);
    EXPECT_EQ(work.threads(), 0);
    ASSERT_TRUE(work.Admit(admission, /*engine_threads=*/3).ok());
    EXPECT_EQ(work.threads(), 3);  // alone: every core, at most the engine's 3
    EXPECT_EQ(admission.stats().running, 1);
    RequestWork second(limits);
    const Status refused = second.Admit(admission, 0);
    EXPECT_EQ(refused.code(), ErrorCode::kUnavailable);
  }
  EXPECT_EQ(admission.stats().running, 0);  // the ticket ends with the request
  RequestWork work(limits);
  ASSERT_TRUE(work.Admit(admission, 0).ok());
  EXPECT_EQ(work.threads(), 4);
}

TEST(RequestWork, ParsesJsonWithinTheDepthLimitNamingTheField) {
  ServiceLimits limits;
  limits.max_json_depth = 3;
  RequestWork work(limits);
  EXPECT_TRUE(work.ParseJson(R"({"a":{"b":1}})", "params").ok());
  auto deep = work.ParseJson(R"({"a":{"b":{"c":{"d":1}}}})", "params");
  ASSERT_FALSE(deep.ok());
  EXPECT_EQ(deep.status().field().rfind("params", 0), 0u) << deep.status().field();
  auto twice = work.ParseJson(R"({"a":1,"a":2})", "body");
  ASSERT_FALSE(twice.ok());
  EXPECT_EQ(twice.status().field().rfind("body", 0), 0u) << twice.status().field();
}

TEST(RequestWork, ImportsTheMeshWithinTheLimitsAndTimesTheParse) {
  ServiceLimits limits;
  RequestWork work(limits);
  auto none = work.Import("");
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.status().code(), ErrorCode::kMalformed);
  EXPECT_EQ(none.status().field(), "mesh");

  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  auto mesh = work.Import(kTriangle);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_EQ(mesh->mesh.positions.size(), 3u);
  EXPECT_GE(work.parse_ms(), 5.0);

  limits.max_vertices = 2;
  RequestWork small(limits);
  auto refused = small.Import(kTriangle);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), ErrorCode::kLimitExceeded);
}

TEST(RequestWork, ASpentBudgetEndsTheParseWithTheRequestsDeadline) {
  ServiceLimits limits;
  limits.request_time_budget_ms = 1;
  RequestWork work(limits);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const Status late = work.EndParse();
  EXPECT_EQ(late.code(), ErrorCode::kDeadlineExceeded);
  EXPECT_NE(late.message().find("parsing"), std::string::npos) << late.message();
  EXPECT_FALSE(work.Import(kTriangle).ok());
}

}  // namespace
}  // namespace surfdeform
