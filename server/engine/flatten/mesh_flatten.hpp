// Flattening a surface given as a triangle mesh: Ma & Lin's
// stress over the mesh's vertices, as for sampled surfaces.
//
// Objective: C = sum over pairs (d_ij - |X_i - X_j|)^2, the pairs being the
// vertices within `range` rings of each other in the mesh (FlattenOptions::
// range counts rings here), d_ij their distance on the mesh.
//
// Distances: the mesh length of the straight segment between the two
// vertices in a near-isometric chart: the segment is traced across the
// chart's triangles and each piece measured through its triangle's affine
// map onto the mesh. Mesh edges are their own length. On a developable mesh
// (a triangulated cylinder) the chart is an isometry, the segment is the
// geodesic and the distance is exact; elsewhere a straight segment of a
// near-isometric chart is a geodesic to second order in its length. The
// first chart is the least-squares conformal map (Levy et al. 2002; its
// boundary free, two vertices pinned), the second the first stress solve's
// result, from which the distances are measured again and the solve
// continued. A pair whose segment leaves the mesh (a concave boundary) is
// left out.
//
// Solver: stress majorization (the Guttman transform with unit weights)
// with the pair graph's Laplacian, grounded at one vertex, factored once
// (Eigen's SimplicialLDLT, AMD ordering) and reused by every iteration, and
// Anderson acceleration as for sampled surfaces (flatten_solvers.hpp).
//
// The result is in a canonical frame: the flat mesh's area centroid at the
// origin, its principal axis of least spread along +Y (the longer side along
// X), counter-clockwise triangles seen from the side the mesh's normals
// point to. A folded triangle is an error (kNotConverged) that counts them.
#pragma once

#include <memory>
#include <vector>

#include "base/status.hpp"
#include "engine/common/disk_mesh.hpp"
#include "engine/common/geometry_types.hpp"
#include "engine/flatten/flatten.hpp"

namespace surfdeform {

// Flattens `mesh`. options.method must be kMajorization; range counts
// rings (1..8); time_budget_ms bounds the whole call (kDeadlineExceeded).
//
// `start`, when given, is a flat layout of the same vertices (the previous
// frame of an animated mesh): the distances are measured along it (it is
// near-isometric for a mesh that moved a little) and the solve starts from
// it, in one round and without the conformal chart; the result is moved
// onto `start` by a rigid motion (centroids matched, turned by the rotation
// of the best affine map between the two: not to the canonical frame), so
// that a sequence of meshes gives sheets that neither jump nor creep round.
// kInvalidArgument when `start` has another size or a non-finite point.
Result<FlatMesh> FlattenMesh(DiskMesh mesh, const FlattenOptions& options,
                             const std::vector<Vec2>* start = nullptr);

// FlattenMesh, keeping what meshes of one topology share between calls: a
// call with a start layout on a mesh of the last call's triangles (an
// animation's next frame) reuses its vertex pairs, which of them the stress
// sums (a pair whose segment now leaves the mesh keeps its distance) and the
// factored Laplacian of their graph, measuring only the distances again.
class MeshFlattener {
 public:
  explicit MeshFlattener(FlattenOptions options = {});
  ~MeshFlattener();
  MeshFlattener(MeshFlattener&&) noexcept;
  MeshFlattener& operator=(MeshFlattener&&) noexcept;

  // `guess`, with a start layout: where the solve starts instead of it (a
  // prediction: the last frames' sheets carried on); the distances are
  // still measured along `start`, which has no folds.
  Result<FlatMesh> Flatten(DiskMesh mesh, const std::vector<Vec2>* start = nullptr,
                           const std::vector<Vec2>* guess = nullptr);

  // New options for the next calls (an animation's time budget, frame by
  // frame); a different range lists the pairs again.
  void set_options(const FlattenOptions& options) { options_ = options; }

  struct Topology;  // (mesh_flatten.cpp)

 private:
  FlattenOptions options_;
  std::unique_ptr<Topology> topology_;
};

// A flattening made before (another replica's, from the shared tier): `mesh`
// with the flat positions `flat` (FlatMesh::flat of a FlattenMesh of it) and
// their quality; the normals are computed again. kInvalidArgument when the
// positions do not fit the mesh (their count, a non-finite or folded one).
Result<FlatMesh> AssembleFlatMesh(DiskMesh mesh, std::vector<Vec2> flat,
                                  const FlattenQuality& quality);

// The vertex pairs within `rings` rings of `reference`'s mesh and their
// distances as the flattening measures them (along its flat layout; pairs
// whose segment leaves the mesh left out): for comparisons with exact
// geodesics.
std::vector<GridEdge> MeshPairDistances(const FlatMesh& reference, int rings, int threads = 0);

// The quality of any layout of `reference`'s mesh (another method's, for
// comparisons) on the flattening's terms: the pairs within 3 rings, their
// distances measured along the reference's own flat layout. A mirrored
// layout (clockwise triangles) is mirrored back first: a reflection keeps
// every distance.
FlattenQuality MeasureMeshLayout(const FlatMesh& reference, std::vector<Vec2> layout,
                                 int threads = 0);

}  // namespace surfdeform
