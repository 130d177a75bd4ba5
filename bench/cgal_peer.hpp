// CGAL's surface parameterizers as a benchmark peer (optional dependency).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "engine/surface/surface.hpp"

namespace surfdeform::bench {

struct PeerResult {
  bool ok = false;
  std::string error;
  std::vector<Vec2> flat;  // per sample, i + nu * j
};

// Samples `surface` on an nu x nv grid, triangulates it (two triangles per cell)
// and parameterizes it with CGAL's ARAP ("arap") or LSCM ("lscm") parameterizer
// with a free border, as CGAL's defaults do.
PeerResult CgalParameterize(const Surface& surface, int nu, int nv, const std::string& method);

// The Delaunay triangulation of points in the plane (CGAL's
// Delaunay_triangulation_2), counter-clockwise, by the points' indices.
std::vector<std::array<int, 3>> DelaunayTriangles(const std::vector<Vec2>& points);

// Exact geodesic distances on a triangle mesh (CGAL's
// Surface_mesh_shortest_path, Chen & Han's algorithm) from vertex `source`
// to every vertex.
std::vector<double> ExactGeodesics(const std::vector<Vec3>& positions,
                                   const std::vector<std::array<int, 3>>& triangles, int source);

// The same for a triangle mesh (a disk): `flat` per vertex.
PeerResult CgalParameterizeMesh(const std::vector<Vec3>& positions,
                                const std::vector<std::array<int, 3>>& triangles,
                                const std::string& method);

}  // namespace surfdeform::bench
