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
#include "engine/flat_locator.hpp"
#include "engine/flatten.hpp"
#include "engine/geometry_types.hpp"
#include "engine/sheet_map.hpp"

namespace surfdeform {

enum class UpAxis { kPosX, kNegX, kPosY, kNegY, kPosZ, kNegZ, kAuto };
inline constexpr EnumEntry<UpAxis> kUpAxes[] = {
    {UpAxis::kPosX, "+x", "the model's +X becomes the surface normal"},
    {UpAxis::kNegX, "-x", "the model's -X becomes the surface normal"},
    {UpAxis::kPosY, "+y", "the model's +Y becomes the surface normal"},
    {UpAxis::kNegY, "-y", "the model's -Y becomes the surface normal"},
    {UpAxis::kPosZ, "+z", "the model's +Z becomes the surface normal"},
    {UpAxis::kNegZ, "-z", "the model's -Z becomes the surface normal"},
    {UpAxis::kAuto, "auto",
     "the API's default: +Y for glTF input (its convention); else the thinnest axis of the "
     "bounding box when it is clearly thinnest (a plate, text, a logo); else +Z"},
};
// Parts of the model that move as rigid bodies (rigid_parts.hpp).
enum class RigidMode { kNone, kComponents, kGroups };
inline constexpr EnumEntry<RigidMode> kRigidModes[] = {
    {RigidMode::kNone, "none", "every vertex follows the surface (the default)"},
    {RigidMode::kComponents, "components",
     "each connected component (after welding by position) moves as one rigid body"},
    {RigidMode::kGroups, "groups",
     "each group of the input (glTF primitive, OBJ group or material) moves as one rigid body"},
};
enum class AnchorMode { kBottom, kCenter, kTop, kValue };
// kValue is given as a number, not a name.
inline constexpr EnumEntry<AnchorMode> kAnchorModes[] = {
    {AnchorMode::kBottom, "bottom", "the model's lowest point along up lands on the surface"},
    {AnchorMode::kCenter, "center", "the middle of its height (the default)"},
    {AnchorMode::kTop, "top", "its highest point"},
};
enum class CenterMode { kSheetCenter, kSheetUnits, kFraction };

struct PlacementOptions {
  UpAxis up = UpAxis::kPosZ;           // model axis that becomes the surface normal
  bool y_up_input = false;             // kAuto: the input's format is Y-up by convention (glTF)
  RigidMode rigid = RigidMode::kNone;  // parts that move as rigid bodies (no subdivision then)
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

Status ValidatePlacement(const PlacementOptions& options);

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
