// Surfaces built in code for tests and benchmarks.
#pragma once

#include <memory>
#include <vector>

#include "engine/flatten/flatten.hpp"
#include "engine/surface/surface_spec.hpp"

namespace surfdeform::testing {

// MakeSurface for specs a test knows to be valid: a failure is a test failure
// (reported through GoogleTest) and returns null.
std::unique_ptr<Surface> MakeValid(const SurfaceSpec& spec);

// The cone of radius r0 at z = 0 and r1 at z = h over angle_deg (at most 360,
// from +X towards +Y) as an exact rational quadratic NURBS (arcs of at most
// 120 degrees), linear in v.
BSplineSpec NurbsCone(double r0, double r1, double h, double angle_deg);

// The surface of revolution of a B-spline profile of (radius, height)
// control points (degree_v, clamped knots_v) about +Z over angle_deg, as an
// exact rational quadratic NURBS in u; periodic_u when it goes all round.
BSplineSpec NurbsRevolution(const std::vector<Vec2>& profile, int degree_v,
                            const std::vector<double>& knots_v, double angle_deg);

// The body and shoulder of a bottle (client/web/samples/bottle.json): a
// NURBS surface of revolution closed in u (periodic_u), radius 1 over the
// middle (exactly a cylinder for v in [0.25, 0.5]), narrowing to 0.85.
BSplineSpec NurbsBottle();

// A cylinder of the given radius and height over angle_deg as a `grid` of
// nu x nv points on it.
GridSpec GridCylinder(double radius, double height, double angle_deg, int nu, int nv);

// A surface and its flat sheet (sampled n x n, default flattening).
struct Target {
  std::unique_ptr<Surface> surface;
  FlatSheet sheet;
};
// A failure to build or flatten is a test failure (then the sheet is empty).
Target Flattened(const SurfaceSpec& spec, int n);

// A flat square sheet [0, 2]^2 with one smooth bump of the given height in the
// quarter around (1.5, 1.5): a uniform cubic B-spline over 10 x 10 control
// points, flat (zero curvature) away from the bump.
BSplineSpec BumpOnAPlane(double height);

}  // namespace surfdeform::testing
