// The local length distortion of a deformation: how much the map from the
// placed model (sheet coordinates a, b and height h) to space stretches or
// shrinks lengths along the sheet at a point.
//
// With J the 3x2 Jacobian d(position)/d(a, b) (the tangential part of the
// deformation's Jacobian; the placement's own scale is not distortion), s1
// >= s2 are its singular values: a length along the sheet is multiplied by
// between s2 and s1. An isometry has s1 = s2 = 1: the mid surface of a plate
// on a cylinder (which unrolls exactly). Off the mid surface the offset adds
// h times the curvature: 1 + h / R across a cylinder of radius R.
#pragma once

#include <vector>

#include "engine/common/geometry_types.hpp"
#include "engine/common/mesh.hpp"

namespace surfdeform {

// (s1, s2), s1 >= s2 >= 0, of a 3x2 matrix.
Vec2 SingularValues(const Eigen::Matrix<double, 3, 2>& jacobian);

// Over the vertices of a mesh with `distortion` set: d = max(|s1 - 1|,
// |s2 - 1|) per vertex; its largest value, its 95th percentile (nearest
// rank), and its mean weighted by each vertex's share of the deformed area
// (a third of each adjacent triangle's; the plain mean when that is zero).
struct DistortionStats {
  bool computed = false;
  double max = 0.0;
  double p95 = 0.0;
  double mean = 0.0;
};
DistortionStats SummarizeDistortion(const Mesh& mesh);

}  // namespace surfdeform
