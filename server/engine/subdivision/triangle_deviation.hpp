// Stage 7b of the subdivision: how far a triangle of a re-triangulated face
// strays from the exact deformation.
//
// Measured at its edge midpoints, its centroid and the three points halfway
// from the centroid to the corners: the exact deformation of the model point
// there against the triangle's linear interpolation of its corners' deformed
// positions. A midpoint on the face's outline is left out: it belongs to the
// edge, which is measured and refined on its own (edge_refinement.hpp).
// Cached per triangle until the triangulation changes it.
#pragma once

#include "engine/subdivision/face_retriangulation.hpp"

namespace surfdeform::subdivision {

class TriangleDeviation {
 public:
  // Counts every measured point in tally->measured.
  TriangleDeviation(const Context& ctx, const std::array<VertexId, 3>& corners,
                    const FaceWork& work, Tally* tally)
      : ctx_(ctx), corners_(corners), work_(work), tally_(tally) {}

  // The deviation of triangle t, output units.
  double operator()(int t, int* hint);

 private:
  struct Cached {
    uint32_t stamp = 0;
    double dev = -1.0;
  };
  const Context& ctx_;
  const std::array<VertexId, 3>& corners_;
  const FaceWork& work_;
  Tally* tally_;
  std::vector<Cached> cache_;
};

}  // namespace surfdeform::subdivision
