// The flat sheets a flattening makes, shared by every stage after it: a
// sampled surface's sheet (FlatSheet), a triangle mesh's (FlatMesh), and
// how good either is (FlattenQuality). The flattening itself is
// flatten/flatten.hpp (sampled surfaces) and flatten/mesh_flatten.hpp
// (meshes); the stages after it read the sheets through this header alone.
#pragma once

#include <string>
#include <vector>

#include "engine/common/disk_mesh.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform {

// Quality of a flat sheet. Stress and the other measures are always taken over
// the r = 3 neighbourhood, whatever range the solve used, so results compare.
struct FlattenQuality {
  double stress = 0.0;          // sqrt(C / sum d_ij^2), dimensionless
  double max_edge_error = 0.0;  // max over grid edges of | |X_i - X_j| - d_ij | / d_ij
  double area_ratio_min = 0.0;  // min over cells of flat area / surface area
  double area_ratio_max = 0.0;
  int folded_cells = 0;  // cells whose flat quad is inverted or not convex
  int iterations = 0;
  bool converged = false;    // reached the tolerance before max_iterations
  double distance_ms = 0.0;  // computing d_ij
  // Pairs measured from the paths an earlier measurement followed
  // (Flattener::Flatten's warm_paths) rather than relaxed afresh; 0 for a
  // cold measurement.
  int refollowed_paths = 0;
  // The step along the warm start's trend that the solve started from
  // (sheet_trend.hpp); 0 when it started from the warm start itself.
  double extrapolated = 0.0;
  double solve_ms = 0.0;  // the solver itself (factorisation included)
  double total_ms = 0.0;  // sampling, distances, solve and quality
};

struct FlatSheet {
  int nu = 0;
  int nv = 0;
  std::vector<Vec3> points;   // surface samples, i + nu * j
  std::vector<Vec3> normals;  // unit surface normals at the samples
  std::vector<Vec2> flat;     // flat positions of the samples, canonical frame
  std::string method;         // "majorization", "paper" or "exact"
  // canonical = frame_linear * solver's + frame_offset (a rotation, and a
  // reflection if the solver's layout was mirrored). With method "exact", maps
  // Surface::ExactUnrolling into this sheet.
  Eigen::Matrix2d frame_linear = Eigen::Matrix2d::Identity();
  Vec2 frame_offset = Vec2::Zero();
  // A sheet flattened periodic in u (PeriodicColumns > 0): its period T, in
  // the canonical frame. Flat points p and p + T are the same surface point;
  // column nu - 1 (the seam again) is column 0 + T. Zero otherwise.
  Vec2 period_u = Vec2::Zero();
  // The same in v (PeriodicRows > 0): row nv - 1 is row 0 + period_v. A
  // surface periodic both ways (a whole torus) is a flat torus.
  Vec2 period_v = Vec2::Zero();
  FlattenQuality quality;
};

// A flattened triangle mesh (FlattenMesh): the mesh, welded and checked, and
// its layout in the plane.
struct FlatMesh {
  DiskMesh mesh;
  std::vector<Vec2> flat;     // per vertex, the canonical frame
  std::vector<Vec3> normals;  // per vertex, unit: the angle-weighted mean of its triangles'
  // stress over the pairs within 3 rings, max_edge_error over mesh edges,
  // area ratios and folded_cells over triangles.
  FlattenQuality quality;
  size_t pairs = 0;          // vertex pairs in the stress (ring <= range)
  size_t dropped_pairs = 0;  // pairs whose straight segment left the mesh
};

}  // namespace surfdeform
