// Subdivision outside the deformation, for tests and benchmarks: the refined
// model with each vertex's placed coordinates and exact deformed position,
// and the deviation measured densely inside every output triangle.
#pragma once

#include <vector>

#include "engine/placement/placement.hpp"
#include "engine/subdivision/subdivide.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform::testing {

struct Refined {
  Mesh model;
  std::vector<Vec3> placed;
  std::vector<Vec3> deformed;
  SubdivisionStats stats;
  bool ok = false;
};

// Places `m` with `o` on the target, subdivides it with `s` and deforms every
// vertex; a failure is a test failure (ok false).
Refined Refine(const Target& t, const Mesh& m, const PlacementOptions& o,
               const SubdivisionOptions& s);

// The largest distance, at 28 points per triangle (a barycentric lattice of
// step 1/6, corners excluded), between the refined mesh's deformed triangles
// and the exact deformation of the model points they stand for.
double DenseDeviation(const Target& t, const Refined& r, OutsideMode outside);

}  // namespace surfdeform::testing
