// What a request says about placing a model on a sheet ("placement" of POST
// /v1/deform and /v1/animate): which axis is up, what lands on the surface,
// where the footprint goes, what happens off the sheet. Plain vocabulary,
// which the API's request types (proto/) share with the engine
// (placement.hpp says what each does); how a placement runs is the engine's
// PlacementOptions, which the service fills.
#pragma once

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"

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

enum class OutsideMode { kError, kClamp, kExtrapolate };
inline constexpr EnumEntry<OutsideMode> kOutsideModes[] = {
    {OutsideMode::kError, "error", "a footprint off the sheet fails (422), saying how far"},
    {OutsideMode::kClamp, "clamp", "points off the sheet move to its nearest boundary point"},
    {OutsideMode::kExtrapolate, "extrapolate", "the nearest boundary cell's map continues"},
};

struct PlacementSettings {
  UpAxis up = UpAxis::kPosZ;                // model axis that becomes the surface normal
  RigidMode rigid = RigidMode::kNone;       // parts that move as rigid bodies (no subdivision then)
  AnchorMode anchor = AnchorMode::kCenter;  // the model height that lands on the surface:
  double anchor_value = 0.0;                // with kValue, in model units along `up`
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
};

// kInvalidArgument naming the field ("placement.scale").
Status ValidatePlacementSettings(const PlacementSettings& settings);

}  // namespace surfdeform
