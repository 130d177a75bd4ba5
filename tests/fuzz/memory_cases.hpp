// Parameter sets that scale a request's memory, drawn at random: for the
// memory fuzz target (libFuzzer's bytes) and the memory estimates' property
// test (a seeded generator). Each is a POST /v1/surfaces body or a POST
// /v1/animate request with the service's own estimate of what it takes
// (FlatteningBytes, AnimationSheetsBytes).
//
// Grids stay at 16 x 16 and below (8 x 8 and 8 frames for animations), so
// that the runs are short; the lattice factor (up to 16) still makes the
// largest take some 15 MB, where an estimate that leaves it out fails by far.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "json/bounded_json.hpp"
#include "proto/api.hpp"
#include "service/limit_checks.hpp"
#include "service/service.hpp"

namespace surfdeform {

// The service the cases run on: one thread, nothing kept between them, and
// a 16 MiB budget that some of them pass (a refusal before the work).
inline constexpr size_t kMemoryCaseBudget = 16u << 20;
inline ServiceOptions MemoryCaseServiceOptions() {
  ServiceOptions o;
  o.engine_threads = 1;
  o.limits.max_grid_side = 16;
  o.limits.flatten_time_budget_ms = 20000;
  o.limits.request_time_budget_ms = 20000;
  o.limits.cache_bytes = 1u << 20;  // every surface flattened anew
  o.limits.answer_cache_bytes = 0;
  o.limits.request_memory_bytes = kMemoryCaseBudget;
  return o;
}

// The request's own objects beside the estimated work: its JSON, the
// reply, the store's entry and the sheet's map: some megabytes for these
// grids.
inline constexpr double kMemoryCaseAllowance = 4.0 * (1 << 20);

struct MemoryCase {
  bool animate = false;
  std::string params;  // the body (surfaces) or the parameters (animate)
  double estimate = 0;
};

// `Draw` gives Int(lo, hi), Real(lo, hi) and Bool().
template <typename Draw>
nlohmann::json DrawSurface(Draw& d, double scale) {
  switch (d.Int(0, 4)) {
    case 0:
      return {{"kind", "cylinder"},
              {"radius", scale},
              {"height", 2 * scale},
              {"angle_deg", d.Real(10.0, 360.0)}};
    case 1:
      return {{"kind", "torus"},
              {"major_radius", 2 * scale},
              {"minor_radius", scale * d.Real(0.1, 0.9)},
              {"u_min_deg", 0},
              {"u_max_deg", d.Real(10.0, 360.0)}};
    case 2:
      return {{"kind", "wave"},
              {"length", 4 * scale},
              {"width", 2 * scale},
              {"amplitude", scale * d.Real(0.0, 0.5)},
              {"wavelength", scale * d.Real(0.3, 3.0)}};
    case 3:
      return {{"kind", "sphere"},   {"radius", scale},
              {"lon_min_deg", 0},   {"lon_max_deg", d.Real(10.0, 180.0)},
              {"lat_min_deg", -60}, {"lat_max_deg", 60}};
    default: {
      nlohmann::json points = nlohmann::json::array();
      for (int k = 0; k < 16; ++k)
        points.push_back({scale * (k % 4), scale * (k / 4), scale * d.Real(-1.0, 1.0)});
      return {{"kind", "bezier"}, {"degree_u", 3}, {"degree_v", 3}, {"control_points", points}};
    }
  }
}

template <typename Draw>
std::optional<MemoryCase> DrawMemoryCase(Draw& d) {
  using nlohmann::json;
  const double scale = std::pow(10.0, d.Real(-2.0, 2.0));
  MemoryCase c;
  c.animate = d.Bool();
  json body;
  body["sampling"] = {{"nu", d.Int(2, c.animate ? 8 : 16)}, {"nv", d.Int(2, c.animate ? 8 : 16)}};
  json flatten = {{"range", d.Int(1, 8)},
                  {"lattice_factor", d.Int(0, 16)},
                  {"relax_steps", d.Int(0, 4)},
                  {"tolerance", std::pow(10.0, d.Real(-9.0, -2.0))}};
  if (d.Int(0, 7) == 0) {
    flatten["method"] = "paper";
    flatten["max_iterations"] = d.Int(1, 50);
  }
  body["flatten"] = flatten;
  if (c.animate) {
    const json from = DrawSurface(d, scale);
    json to = from;
    for (auto& [key, value] : to.items()) {
      if (value.is_number() && key != "degree_u" && key != "degree_v") {
        value = value.template get<double>() * d.Real(0.8, 1.2);
      }
    }
    body["animation"] = {
        {"keyframes", {{{"time", 0}, {"surface", from}}, {{"time", 1}, {"surface", to}}}},
        {"frames", d.Int(2, 8)}};
    body["placement"] = {{"scale", "fit"}};
    body["subdivision"] = {{"mode", "off"}};
    c.params = body.dump();
    auto parsed = ParseBoundedJson(c.params, {}, "params");
    if (!parsed.ok()) return std::nullopt;
    auto params = proto::ParseAnimateParams(*parsed);
    if (!params.ok()) return std::nullopt;
    c.estimate = AnimationSheetsBytes(params->animation);
  } else {
    body["surface"] = DrawSurface(d, scale);
    c.params = body.dump();
    auto parsed = ParseBoundedJson(c.params, {}, "body");
    if (!parsed.ok()) return std::nullopt;
    auto create = proto::ParseCreateSurfaceRequest(*parsed);
    if (!create.ok()) return std::nullopt;
    c.estimate = FlatteningBytes(create->request.sampling, create->request.flatten);
  }
  return c;
}

// The case's request through the service.
inline Result<Reply> RunMemoryCase(Service& service, const MemoryCase& c) {
  static const std::string kModel = "v -0.2 -0.1 0\nv 0.2 -0.1 0\nv 0 0.2 0.05\nf 1 2 3\n";
  if (!c.animate) return service.CreateSurface(c.params);
  DeformRequest request;
  request.params = c.params;
  request.mesh = kModel;
  return service.Animate(request);
}

// Refused at the memory budget: its limit is the budget.
inline bool RefusedForMemory(const Result<Reply>& reply) {
  return !reply.ok() && reply.status().code() == ErrorCode::kLimitExceeded &&
         reply.status().has_limit() &&
         reply.status().limit() == static_cast<double>(kMemoryCaseBudget);
}

}  // namespace surfdeform
