// The request-cost fuzzer's service and inputs, shared by estimate_fuzzer.cpp
// and the unit test that replays its committed seeds
// (HostileInput.EveryEstimateSeedIsAnsweredWithoutUndefinedBehaviour).
#pragma once

#include <string_view>

#include "service/service.hpp"

namespace surfdeform {

// The service the fuzzer asks: the published output limits and memory
// budget, short time budgets, one request at a time.
inline ServiceOptions EstimateServiceOptions(double budget_ms) {
  ServiceOptions o;
  o.engine_threads = 1;
  o.limits.max_body_bytes = 64 << 10;
  o.limits.max_grid_side = 32;  // the estimates are about the mesh, not the grid
  o.limits.flatten_time_budget_ms = budget_ms;
  o.limits.request_time_budget_ms = budget_ms;
  o.limits.max_in_flight = 1;
  o.limits.max_queued = 0;
  o.limits.cache_bytes = 8u << 20;
  return o;
}

// An input as a request: the deformation's parameters (JSON, the first
// line) and a small mesh (the rest), as views of `input`; false without a
// first line.
inline bool EstimateRequest(std::string_view input, DeformRequest* request) {
  const size_t line = input.find('\n');
  if (line == std::string_view::npos) return false;
  request->params = input.substr(0, line);
  request->mesh = input.substr(line + 1);
  return true;
}

}  // namespace surfdeform
