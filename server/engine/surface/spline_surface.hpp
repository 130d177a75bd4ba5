// Tensor-product spline patches: Bezier (as a clamped B-spline with one span),
// B-spline and NURBS, and the C2 interpolating spline behind the `grid` kind.
// Evaluation: basis functions of The NURBS Book (A2.3), rational derivatives by
// the quotient rule (ibid. A4.4), up to second order.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/surface/surface.hpp"

namespace surfdeform {

struct SplineData {
  int degree_u = 0;
  int degree_v = 0;
  int count_u = 0;
  int count_v = 0;
  std::vector<Vec3> control_points;  // count_u * count_v, u fastest
  std::vector<double> knots_u;       // count_u + degree_u + 1, clamped (unless closed_u)
  std::vector<double> knots_v;
  std::vector<double> weights;  // empty, or one per control point
  bool closed_u = false;        // S(0, v) = S(1, v) (checked by the caller): Surface::ClosedInU
  bool closed_v = false;        // S(u, 0) = S(u, 1) likewise: Surface::ClosedInV
};

// Builds a spline surface from already validated data (see MakeSurface).
std::unique_ptr<Surface> MakeSplineSurface(SplineData data, const char* kind);

// Control net of the clamped cubic B-splines (natural end conditions) that
// interpolate each column of `values` (n rows, n >= 2) at n uniform parameters
// i / (n - 1). Returns n + 2 rows of control values and fills `knots`
// (n + 6 values). One factorisation serves every column.
Eigen::MatrixXd InterpolateCubicNatural(const Eigen::MatrixXd& values, std::vector<double>* knots);

// The same for closed curves: the last row of `values` repeats the first
// (n >= 4), and the uniform cubic B-spline that interpolates them is
// periodic, C2 across the seam: n + 2 rows of control values (the last
// three repeating the first three) over n + 6 unclamped uniform knots, its
// domain [0, 1].
Eigen::MatrixXd InterpolateCubicPeriodic(const Eigen::MatrixXd& values, std::vector<double>* knots);

}  // namespace surfdeform
