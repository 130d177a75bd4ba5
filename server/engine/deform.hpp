// Laying a model on a flat sheet and carrying it onto the surface (the paper's
// section 3.2 without refinement; see subdivide for the refinement).
//
// Placement: the model axis `up` becomes the surface normal; the model's
// height along it, measured from `anchor`, becomes the distance h along the
// normal. The other two axes (right-handed with `up`) give the in-plane
// footprint (a, b), which is rotated by rotation_deg about its centre, scaled
// by `scale` (or the largest scale that keeps it inside the sheet with a
// margin, `fit`), and centred at `center` on the flat sheet. Units are the
// model's and the surface's own.
//
// Deformation of each vertex: locate its footprint (a, b) in the flat sheet
// (FlatLocator, O(1)), invert the cell's bilinear map exactly to surface
// parameters (u, v), evaluate the surface exactly there (not interpolated from
// the grid) and place the vertex at S(u, v) + h N(u, v). Normals and tangents
// follow the map's Jacobian (normals by its inverse transpose), so hard edges
// stay hard; texture coordinates, colours and groups carry over unchanged, and
// the vertex order and count are kept. Parallel over vertices; the result does
// not depend on the thread count.
#pragma once

#include <string>

#include "engine/flatten.hpp"
#include "engine/mesh.hpp"
#include "engine/status.hpp"
#include "engine/surface.hpp"

namespace surfdeform {

enum class UpAxis { kPosX, kNegX, kPosY, kNegY, kPosZ, kNegZ };
enum class AnchorMode { kBottom, kCenter, kTop, kValue };
enum class CenterMode { kSheetCenter, kSheetUnits, kFraction };
enum class OutsideMode { kError, kClamp, kExtrapolate };

struct PlacementOptions {
  UpAxis up = UpAxis::kPosZ;                          // model axis that becomes the surface normal
  AnchorMode anchor = AnchorMode::kCenter;            // the model height that lands on the surface:
  double anchor_value = 0.0;                          // with kValue, in model units along `up`
  CenterMode center_mode = CenterMode::kSheetCenter;  // where the footprint centre goes:
                                                      // kSheetCenter: the image of the
                                                      // surface's (u, v) = (1/2, 1/2);
  Vec2 center = Vec2::Zero();  // kSheetUnits: flat-sheet point; kFraction: of the sheet's
                               // bounding box, (0, 0) = its min corner, (1, 1) = max corner
  double rotation_deg = 0.0;   // footprint rotation about its centre, counter-clockwise
  double scale = 1.0;          // uniform scale of the model (ignored with fit)
  bool fit = false;            // largest scale that keeps the footprint inside the sheet
  double fit_margin = 0.02;    // with fit: margin, as a fraction of the sheet's smaller side
  OutsideMode outside = OutsideMode::kError;  // footprint points outside the sheet:
  // kError: fail and say how many and how far; kClamp: move them to the nearest
  // point of the sheet's boundary; kExtrapolate: continue the nearest boundary
  // cell's map past the boundary (continuous; the surface is evaluated past its
  // parameter range, where every kind continues smoothly).
  int threads = 0;  // 0 = one per core
};

struct DeformStats {
  size_t vertices = 0;
  size_t triangles = 0;
  size_t outside = 0;  // footprint points outside the sheet (clamped or extrapolated)
  double max_outside_distance = 0.0;  // the farthest of them from the sheet, sheet units
  double scale = 1.0;                 // the scale used (the fitted one with fit)
  double time_ms = 0.0;
};

struct DeformResult {
  Mesh mesh;
  DeformStats stats;
};

Status ValidatePlacement(const PlacementOptions& options);

// Errors: kInvalidArgument for bad options or a malformed mesh; kDegenerate for
// a footprint that cannot be fitted or a deformation that would produce
// non-finite values; kOutsideSheet, with the count and the worst distance,
// when the footprint leaves the sheet and outside = kError.
Result<DeformResult> DeformMesh(const Surface& surface, const FlatSheet& sheet, const Mesh& mesh,
                                const PlacementOptions& options);
// The same, reusing the input's buffers (no copy of the mesh): for callers
// that no longer need the undeformed mesh.
Result<DeformResult> DeformMesh(const Surface& surface, const FlatSheet& sheet, Mesh&& mesh,
                                const PlacementOptions& options);

}  // namespace surfdeform
