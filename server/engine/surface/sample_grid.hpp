// Sampling a surface on a regular nu x nv parameter grid.
#pragma once

#include <vector>

#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"
#include "engine/surface/sampling_options.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

// Sample (i, j) sits at (u, v) = (i / (nu - 1), j / (nv - 1)); index i + nu * j.
struct SampledGrid {
  int nu = 0;
  int nv = 0;
  std::vector<Vec3> points;
  std::vector<Vec3> normals;  // unit normals
  int index(int i, int j) const { return i + nu * j; }
};

// Errors: kInvalidArgument for a grid size out of range; kDegenerate naming the
// first sample whose position is not finite or whose normal vanishes (a pole, an
// apex, a collapsed row of control points).
Result<SampledGrid> SampleSurface(const Surface& surface, const SamplingOptions& options);

}  // namespace surfdeform
