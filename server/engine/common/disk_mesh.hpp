// A triangle mesh given as a surface: checked to be a topological
// disk before it is flattened.
//
// What is accepted: a connected, manifold, consistently oriented triangle
// mesh with exactly one boundary loop and no handles (V - E + F = 1).
// Vertices closer than a tolerance are welded first (scans and tessellated
// CAD faces repeat them along seams), and vertices no triangle uses are
// dropped. Every refusal names the first offending element and what to do
// about it, in the order: zero-area triangles, edges shared by more than two
// triangles, flipped orientation, non-manifold vertices, several components,
// a closed mesh, holes, handles.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform {

struct DiskMeshOptions {
  // Vertices closer than this fraction of the bounding box's diagonal are one.
  double weld_tolerance = 1e-9;
  // Triangles whose area is below this fraction of the squared diagonal are
  // refused as zero-area.
  double min_area = 1e-14;
  size_t max_vertices = 0;  // after welding; 0 = no limit
};

struct DiskMesh {
  std::vector<Vec3> positions;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from the normal's side
  // neighbours[f][k]: the triangle across edge k of triangle f (from corner
  // k to corner k + 1), -1 on the boundary.
  std::vector<std::array<int, 3>> neighbours;
  std::vector<int> boundary;  // the boundary loop, in the triangles' direction
  size_t welded = 0;          // input vertices merged into another
  size_t dropped = 0;         // input vertices no triangle used
};

// The first triangle of `mesh` whose area is not above `min_area` (an
// absolute area), or -1.
int CollapsedTriangle(const DiskMesh& mesh, double min_area);

// Welds, checks and returns the disk; kDegenerate (422) naming the first
// offending element otherwise, kLimitExceeded past max_vertices, and
// kInvalidArgument for indices out of range or non-finite positions.
Result<DiskMesh> MakeDiskMesh(const std::vector<Vec3>& positions,
                              const std::vector<std::array<uint32_t, 3>>& triangles,
                              const DiskMeshOptions& options = {});

}  // namespace surfdeform
