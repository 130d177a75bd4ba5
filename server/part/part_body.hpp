// A part's body from a surface: the surface thickened along its normal into
// a closed solid. A surface closed in u (a whole cylinder, a cone, a
// bottle) gives a closed band, closed both ways (a whole torus) a closed
// ring; an open patch gets side walls along its borders. Lengths are the
// surface's units, which a part reads as millimetres.
#pragma once

#include <array>

#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "engine/surface/surface.hpp"
#include "part/part_settings.hpp"

namespace surfdeform {

struct BodyOptions {
  double thickness = 1.0;
  BodySide side = BodySide::kOutside;
  // Samples per side of the parameter square (a closed direction's last
  // sample is its first).
  int nu = 64;
  int nv = 64;
};

// Samples per side for a body that follows the surface to within
// `step_deg` of turning between neighbours: the surface's normal measured
// on a 33 x 33 grid, the most it turns along u (and v) over a row, cut into
// steps; at least 2, at most `most`. A whole cylinder: 144 round, 2 along.
std::array<int, 2> BodySamples(const Surface& surface, double step_deg = 2.5, int most = 512);

// The heights of the body's two faces along the normal, low first.
std::array<double, 2> BodyHeights(const BodyOptions& o);

// The body, its triangles oriented outward, every edge shared by exactly
// two triangles. kDegenerate where the surface has no normal (a pole, a
// collapsed edge) or where the thickness on the material's side exceeds
// the surface's radius of curvature (the offset face would fold), naming
// where and the largest thickness possible; kInvalidArgument for a
// thickness that is not positive or a grid under 2 x 2 samples.
Result<Mesh> ThickenSurface(const Surface& surface, const BodyOptions& o);

// Triangles ThickenSurface makes, before making them (for the caller's
// limits): two skins and the walls of the open borders.
size_t BodyTriangles(const Surface& surface, const BodyOptions& o);

}  // namespace surfdeform
