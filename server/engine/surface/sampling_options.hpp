// How finely a surface is sampled for its flattening ("sampling" of POST
// /v1/surfaces): plain vocabulary, which the API's request types (proto/)
// share with the engine (sample_grid.hpp).
#pragma once

#include "base/status.hpp"

namespace surfdeform {

inline constexpr int kMinGridSide = 2;
inline constexpr int kMaxGridSide = 512;

struct SamplingOptions {
  int nu = 16;  // samples along u, 2..512
  int nv = 16;  // samples along v, 2..512
};

// kInvalidArgument naming the field ("nu") for a grid size out of range.
Status ValidateSampling(const SamplingOptions& options);

}  // namespace surfdeform
