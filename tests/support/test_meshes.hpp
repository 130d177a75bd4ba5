// Meshes built in code for tests and benchmarks.
#pragma once

#include <string>

#include "engine/common/mesh.hpp"
#include "engine/placement/placement.hpp"

namespace surfdeform::testing {

// Placement that keeps model coordinates: the model's origin at sheet point
// `at`, heights from z = 0, scale 1; so (a, b, h) = (x + at.x, y + at.y, z)
// for a model whose bounding box is centred on the origin in x and y.
PlacementOptions KeepCoordinates(const Mesh& m, const Vec2& at);

// The paper's thin plate: a box of 6 quads (12 triangles, 8 shared vertices),
// size_x x size_y x thickness, centred at the origin, outward winding.
Mesh ThinPlate(double size_x, double size_y, double thickness);

// `count` thin plates (0.4 x 0.6 x 0.1, 8 vertices each, in order) in a row
// along x, evenly over [-length / 2, length / 2], standing on z = 0:
// glyphs to go all round a closed surface.
Mesh GlyphRow(int count, double length);

// The largest relative change of a distance between two vertices of the
// same glyph (8 consecutive vertices) from `before` to `after`.
double WorstGlyphStretch(const Mesh& before, const Mesh& after);

// A flat grid of (nx + 1) x (ny + 1) vertices over [x0, x0 + sx] x [y0, y0 + sy]
// at height z, with normals +Z, tangents +X, uv0 = (x, y) and per-vertex
// colours, triangulated.
Mesh FlatGrid(double x0, double y0, double sx, double sy, int nx, int ny, double z);

// A closed, manifold, outward-wound UV sphere of `slices` x `stacks` quads
// (poles as triangle fans), centred at the origin.
Mesh UvSphere(double radius, int slices, int stacks);

// Edge-manifold check by position: every edge (vertices matched by exact
// position) is used by exactly two triangles, once in each direction, and no
// triangle repeats a position. Returns the first violation, or "".
std::string ClosedManifoldProblem(const Mesh& mesh);

}  // namespace surfdeform::testing
