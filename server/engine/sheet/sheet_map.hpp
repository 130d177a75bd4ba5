// The map from the flat sheet back onto the surface, for a point of the sheet
// and a height: F(a, b, h) = S(u, v) + h N(u, v), where (u, v) are the surface
// parameters of the flat point (a, b).
//
// (a, b) -> (u, v): the exact inverse of the bilinear map of the sheet cell
// that holds (a, b) (FlatLocator, O(1)); for analytic cylinders and cones
// unrolled in closed form, the inverse of that unrolling (exact). The surface
// is evaluated exactly at (u, v), never interpolated from the grid. Used by the
// deformation for every vertex and by the subdivision for every point it
// measures or adds, so both see the same map.
#pragma once

#include <memory>

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/flat_sheet.hpp"
#include "engine/common/geometry_types.hpp"
#include "engine/common/placement_settings.hpp"
#include "engine/flatten/seam_extension.hpp"
#include "engine/sheet/flat_locator.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

// Where a flat point lands on the surface.
struct SheetParameters {
  Vec2 uv = Vec2::Zero();
  Eigen::Matrix2d duv = Eigen::Matrix2d::Zero();  // d(u, v)/d(a, b), when asked for
  bool outside = false;                           // (a, b) is not on the sheet
  double outside_distance = 0.0;                  // then: its distance from the sheet
  int cell = -1;           // the sheet cell that holds (a, b) (cell-wise maps only; else -1)
  SheetLocation location;  // where in that cell (meaningful where cell >= 0)
};

// kOutsideSheet: `count` of `n` vertices fall outside the sheet, the farthest
// `worst` sheet units away, and what to do about it.
Status OutsideSheetError(size_t count, size_t n, double worst);

class SheetMap {
 public:
  // Keeps references: `surface` and `sheet` must outlive the map. A surface
  // closed in u on its closed-form unrolling (PeriodicInU) is mapped through
  // its sheet continued past the seam (seam_extension.hpp): surface(),
  // sheet() and locator() are then the extended ones, and parameters
  // (SheetParameters::uv) are the extended surface's; given_sheet() and
  // GivenParameters() are what the caller gave. `seam_columns` is the
  // extension's columns each side (-1: as many as the sheet allows; 0: none,
  // the sheet is mapped as it is): the frames of an animation share one.
  SheetMap(const Surface& surface, const FlatSheet& sheet, int seam_columns = -1);

  // The parameters of flat point `ab`. Outside the sheet: kClamp moves the
  // point to the nearest point of the sheet's boundary, kExtrapolate continues
  // the nearest boundary cell's map (the surface is evaluated past its
  // parameter range, where every kind continues smoothly); with kError the
  // result is only flagged (and uv is unspecified). `hint` is the cell to try
  // first (the previous point's), updated; may be null.
  SheetParameters Parameters(const Vec2& ab, OutsideMode outside, bool want_jacobian,
                             int* hint) const;
  // The same for a point found on the sheet before, at `location` (the
  // `location` of a result with cell >= 0): the same bits, without the search.
  SheetParameters ParametersAt(const SheetLocation& location, bool want_jacobian) const;

  // The flat point of surface parameters (u, v): the inverse of Parameters
  // (the cell's bilinear map; the closed-form unrolling for exact kinds).
  // (u, v) outside [0, 1]^2 continue the border cell's map.
  Vec2 SheetPoint(const Vec2& uv) const;
  // F(a, b, h): the position only. Outside points as kExtrapolate unless
  // `outside` says otherwise (kError is taken as kExtrapolate here: callers
  // that must refuse outside points check Parameters first).
  Vec3 Position(const Vec3& abh, OutsideMode outside, int* hint) const;
  // The surface point S and unit normal N under flat point `ab` (as Position
  // takes `outside`): Position(a, b, h) = S + h N, for callers that need
  // several heights at one point.
  void SurfaceAndNormal(const Vec2& ab, OutsideMode outside, int* hint, Vec3* point,
                        Vec3* normal) const;

  // On a surface that covers part of its parameter square (a mesh): how
  // deep flat point `ab` lies in it (Surface::DomainDepth); else std::nullopt.
  std::optional<double> DomainDepth(const Vec2& ab) const;

  // Parameters are found by locating the point's cell (else the map inverts
  // a closed-form unrolling, and there is no cell to keep).
  bool cell_wise() const { return !exact_; }
  const FlatLocator& locator() const { return locator_; }
  const FlatSheet& sheet() const { return sheet_; }
  const Surface& surface() const { return surface_; }

  // The sheet as given (placement resolves its centre and margin there) and
  // its locator: the mapping's own unless the sheet is extended.
  const FlatSheet& given_sheet() const { return given_sheet_; }
  const FlatLocator& given_locator() const { return given_locator_ ? *given_locator_ : locator_; }
  // Whether a model may cross the seam (the sheet is extended); then the
  // columns of one period of locator()'s grid.
  bool periodic_u() const { return extension_ != nullptr && extension_->period_columns > 0; }
  int period_columns() const { return extension_ ? extension_->period_columns : 0; }
  // The same in v (a whole torus, a tube): rows of one period of locator()'s grid.
  bool periodic_v() const { return extension_ != nullptr && extension_->period_rows > 0; }
  int period_rows() const { return extension_ ? extension_->period_rows : 0; }
  // The given surface's parameters of this map's (u in [0, 1) when periodic).
  Vec2 GivenParameters(const Vec2& uv) const {
    return extension_ ? extension_->GivenParameters(uv) : uv;
  }
  // This map's parameters of the given surface's (the middle copy).
  Vec2 MapParameters(const Vec2& given_uv) const {
    return extension_ ? extension_->ExtendedParameters(given_uv) : given_uv;
  }

 private:
  // d(u, v)/d(a, b) in the cell of `l`.
  Eigen::Matrix2d ParameterJacobian(const SheetLocation& l) const;

  std::shared_ptr<const SeamExtension> extension_;  // before the references into it
  const FlatSheet& given_sheet_;
  const Surface& surface_;
  const FlatSheet& sheet_;
  FlatLocator locator_;
  std::shared_ptr<const FlatLocator> given_locator_;  // when extended
  bool exact_ = false;  // invert the closed-form unrolling instead of the cells
  Eigen::Matrix2d raw_from_sheet_ = Eigen::Matrix2d::Identity();
  double sheet_size_ = 1.0;  // diagonal of the sheet's bounding box
};

// The unit normal and the Jacobian d F / d(a, b, h) at a flat point with
// parameters `p` and height h, from the surface's first and second
// derivatives `s` there (Weingarten: the normal's derivatives follow from
// the second derivatives). Columns: d/da, d/db, d/dh (= N).
Eigen::Matrix3d DeformJacobian(const SurfacePoint& s, const SheetParameters& p, double h,
                               Vec3* unit_normal);

}  // namespace surfdeform
