// Meshes built in code for tests and benchmarks.
#pragma once

#include "engine/mesh.hpp"

namespace surfdeform::testing {

// The paper's thin plate: a box of 6 quads (12 triangles, 8 shared vertices),
// size_x x size_y x thickness, centred at the origin, outward winding.
Mesh ThinPlate(double size_x, double size_y, double thickness);

// A flat grid of (nx + 1) x (ny + 1) vertices over [x0, x0 + sx] x [y0, y0 + sy]
// at height z, with normals +Z, tangents +X, uv0 = (x, y) and per-vertex
// colours, triangulated.
Mesh FlatGrid(double x0, double y0, double sx, double sy, int nx, int ny, double z);

}  // namespace surfdeform::testing
