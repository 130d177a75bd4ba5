// Placing a model on a flat sheet: which model axis becomes the surface
// normal, which model height lands on the surface, and where the footprint
// goes on the sheet (centre, rotation, scale or fit).
//
// The model axis `up` becomes the surface normal; the model's height along
// it, measured from `anchor`, becomes the distance h along the normal. The
// other two axes (right-handed with `up`) give the in-plane footprint (a, b),
// which is rotated by rotation_deg about its centre, scaled by `scale` (or the
// largest scale that keeps it inside the sheet with a margin, `fit`), and
// centred at `center` on the flat sheet. Units are the model's and the
// surface's own. The placement is affine: interpolating model points and
// placing them commute, which the subdivision relies on.
#pragma once

#include <span>
#include <vector>

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/flat_sheet.hpp"
#include "engine/common/geometry_types.hpp"
#include "engine/common/placement_settings.hpp"
#include "engine/sheet/flat_locator.hpp"
#include "engine/sheet/sheet_map.hpp"

namespace surfdeform {

// A placement as the engine runs it: the request's settings, what the
// service knows of the input (its format's convention) and how it runs.
struct PlacementOptions : PlacementSettings {
  bool y_up_input = false;  // kAuto: the input's format is Y-up by convention (glTF)
  // The footprint's centre is the model's origin, not its bounding box's
  // centre: a text's baseline centre goes to the placement's centre.
  bool centre_at_origin = false;
  int threads = 0;  // 0 = one per core
};

Status ValidatePlacement(const PlacementOptions& options);  // the settings, then threads

// A model point p goes to placed coordinates Apply(p) = (a, b, h): a flat
// point (a, b) of the sheet and a height h along the surface normal.
struct Placement {
  Eigen::Matrix3d basis = Eigen::Matrix3d::Identity();  // model -> (a, b, h) directions
  Vec2 centre = Vec2::Zero();  // footprint centre, in (a, b) before the transform
  double h0 = 0.0;             // model height that lands on the surface
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  double scale = 1.0;
  Vec2 target = Vec2::Zero();       // where the centre goes on the sheet
  UpAxis up = UpAxis::kPosZ;        // the axis used (kAuto resolved)
  const char* up_reason = "given";  // "given", or kAuto's: "gltf", "thinnest", "default"

  Vec3 Apply(const Vec3& p) const {
    const Vec3 q = basis * p;
    const Vec2 ab = target + scale * (rotation * (q.head<2>() - centre));
    return Vec3(ab.x(), ab.y(), scale * (q.z() - h0));
  }
  // The linear part of Apply.
  Eigen::Matrix3d Linear() const {
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    r.topLeftCorner<2, 2>() = rotation;
    return scale * r * basis;
  }
};

// What kAuto chooses for a model with these positions (sets *reason to
// "gltf", "thinnest" or "default"): +Y when y_up_input; else the positive
// axis along which the bounding box is at most half as thick as along the
// next thinnest; else +Z. Other axes are returned as they are ("given").
UpAxis ResolveUpAxis(UpAxis up, bool y_up_input, const std::vector<Vec3>& positions,
                     const char** reason);

// The placement of a model with these vertex positions (all finite) on the
// map's given sheet. With fit on a sheet continued past its seam
// (SheetMap::periodic_u), the footprint may cross the seam but not go round
// more than once. Errors: kDegenerate for a footprint that cannot be
// fitted, kOutsideSheet when the fit's centre is off the sheet.
Result<Placement> ComputePlacement(const SheetMap& map, const std::vector<Vec3>& positions,
                                   const PlacementOptions& options);

// On a sheet continued past its seam (SheetMap::periodic_u): how far round
// the surface the model's footprint goes, in turns (its outline's extent in
// u over one period's); past 1 the model lies over itself. 0 on other
// sheets.
double TurnsRound(const SheetMap& map, const Placement& placement, std::span<const Vec3> positions);

// One model's placements on the sheets of an animation's frames (one grid).
// Each frame resolves the placement on its own sheet, as ComputePlacement
// does: "center" is the image of the surface point (1/2, 1/2) on that sheet,
// so the model stays on that surface point as the surface moves, and the
// frames on keys equal the static placements on the keys. The scale is one
// for all: the given one, or with fit the largest that fits every frame.
struct FramePlacements {
  std::vector<Placement> each;  // per sheet
  int fit_frame = -1;           // with fit: the frame whose sheet decided the scale
};
// Errors as ComputePlacement's, prefixed with the frame ("frame 11: ...").
Result<FramePlacements> ComputeFramePlacements(std::span<const SheetMap* const> maps,
                                               const std::vector<Vec3>& positions,
                                               const PlacementOptions& options);

}  // namespace surfdeform
