// What a request says about refining the deformed model ("subdivision" of
// POST /v1/deform and /v1/animate). Plain vocabulary, which the API's request
// types (proto/) share with the engine (subdivide.hpp); the output limits,
// budget and threads are the engine's SubdivisionOptions, which the service
// fills.
#pragma once

#include "base/status.hpp"
#include "engine/subdivision/subdivision_mode.hpp"

namespace surfdeform {

struct SubdivisionSettings {
  SubdivisionMode mode = SubdivisionMode::kAdaptive;
  // Curvature threshold, 1 / surface units (the paper's epsilon); 0 = none.
  double epsilon = 0.0;
  // Largest deviation from the exact deformation, output (surface) units;
  // 0 = none when epsilon is given, else automatic: 1e-3 of the diagonal of
  // the flat sheet's bounding box.
  double tolerance = 0.0;
};

// kInvalidArgument naming the field ("subdivision.tolerance").
Status ValidateSubdivisionSettings(const SubdivisionSettings& settings);

}  // namespace surfdeform
