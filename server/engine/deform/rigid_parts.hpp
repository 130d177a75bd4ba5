// Rigid parts (text, logos, bolts): parts of a model that move onto the
// surface as rigid bodies instead of bending with it (Rhino's Rigid and
// RigidGroups options of FlowAlongSrf).
//
// A part's placed coordinates (a, b, h) (placement.hpp) are moved as one:
// its footprint's centre c (the middle of its (a, b) bounding box, at h = 0)
// lands at S(c); its height axis along the unit normal N there; its sheet
// axes along the sheet's local frame there (the images of the a and b
// directions, made orthonormal: Gram-Schmidt). So every distance within a
// part is kept (to rounding), letters follow the curve of a bottle from one
// to the next, and each keeps its shape. Parts may be larger than a sheet
// cell; their flat footprint then leaves the curved surface at its corners,
// which the stats report: the signed distance, along the surface normal
// under each corner of the footprint box, of the part's plane h = 0 from the
// surface (positive: lifts off; negative: sinks in).
#pragma once

#include <vector>

#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "engine/placement/placement.hpp"
#include "engine/sheet/sheet_map.hpp"

namespace surfdeform {

// The part of each vertex (0 .. *count - 1). kComponents: connected by
// triangles after welding vertices with equal positions (a vertex in no
// triangle is a part of its own); kGroups: the input unit (MeshGroup::part:
// glTF node, OBJ g/o group; else the MeshGroup itself) of the first triangle
// that uses it (the whole mesh for no groups; unused vertices join the
// first part). kNone: every vertex its own part.
std::vector<int> RigidParts(const Mesh& mesh, RigidMode mode, int* count);

struct RigidPartStats {
  size_t vertices = 0;
  bool outside = false;  // its centre is off the sheet
  double lift = 0.0;     // the largest distance a footprint corner lifts off the surface (>= 0)
  double sink = 0.0;     // the largest distance one sinks in (>= 0)
};
struct RigidStats {
  RigidMode mode = RigidMode::kNone;
  size_t parts = 0;
  double max_lift = 0.0;
  double max_sink = 0.0;
  size_t outside = 0;  // parts whose centre is off the sheet (clamped or extrapolated)
  double max_outside_distance = 0.0;
  std::vector<RigidPartStats> each;  // per part, in part order
};

// Places every part of `in` rigidly into out->positions (and normals and
// tangents, rotated), sized like `in`. Parts whose centre is off the sheet
// follow `outside` (kError: counted only; the caller refuses).
RigidStats PlaceRigidParts(const SheetMap& map, const Placement& placement, const Mesh& in,
                           const std::vector<int>& part, int parts, OutsideMode outside, Mesh* out);

}  // namespace surfdeform
