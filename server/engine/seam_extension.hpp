// A sheet of a surface closed in u (issue #36), continued past its seam, so
// that a model may lie across the seam and wrap round the surface.
//
// The sheet a surface is flattened to is cut at the seam u = 0 = 1. The
// extension adds columns on both sides that continue the sheet: flat points
// of the surface's parameters past [0, 1] in u (a period each side
// where the plane allows it), which are the same surface points again. With
// the surface reparametrised over the extended columns (u' in [0, 1] over
// them; evaluation wraps u into the surface's [0, 1)), the extension is a
// surface and a sheet like any other: locating, mapping, subdividing and
// placing run on it unchanged. A point and the point one period away on the
// extended sheet map to the same surface point.
//
// Phase one: sheets unrolled in closed form (a full cylinder: the strip
// continues by the translation (2 pi R, 0); a full cone: the annular sector
// continues by a rotation about the apex, as far as the plane allows before
// the continued sector would meet itself).
#pragma once

#include <memory>
#include <optional>

#include "engine/flatten.hpp"
#include "engine/surface.hpp"

namespace surfdeform {

// A surface closed in u over the parameters u' in [0, 1] for its
// u = u0 + u_scale u', wrapped into [0, 1); derivatives scaled to match.
// Keeps a reference to `given`.
std::unique_ptr<const Surface> ContinuedInU(const Surface& given, double u0, double u_scale);

// Whether a model on `sheet` may cross the seam of `surface`: the surface
// closes in u and the sheet is its closed-form unrolling or was flattened
// periodic (FlatSheet::period_u).
bool PeriodicInU(const Surface& surface, const FlatSheet& sheet);

// The rigid motion of the plane that takes the seam's column u = 0 of a
// periodic sheet onto its column u = 1 (the same surface points): a flat
// point p and rotation(angle) p + translation are one surface point. A
// cylinder's is the translation (2 pi R, 0); a cone's, the rotation by its
// sector's angle about the apex.
struct SheetPeriod {
  double angle = 0.0;  // radians, counter-clockwise
  Vec2 translation = Vec2::Zero();
};
// The period of a periodic sheet (PeriodicInU), else std::nullopt.
std::optional<SheetPeriod> PeriodOf(const Surface& surface, const FlatSheet& sheet);

struct SeamExtension {
  std::unique_ptr<const Surface> surface;  // the given one over the extended columns
  FlatSheet sheet;                         // nu + 2 columns, the given columns in the middle
  int columns = 0;                         // added on each side
  int period_columns = 0;                  // columns of one period: the given sheet's nu - 1
  double u0 = 0.0;                         // the given surface's u at extended u' = 0
  double u_scale = 1.0;                    // d(given u)/d(extended u')

  // The given surface's parameters of extended parameters, u in [0, 1).
  Vec2 GivenParameters(const Vec2& extended) const;
  // The extended parameters of the given surface's (u in [0, 1]: the middle copy).
  Vec2 ExtendedParameters(const Vec2& given) const;
};

// The columns the extension of a periodic sheet adds on each side: a period,
// or fewer where the plane leaves less room (a cone's sector continued past
// half a turn from its middle would meet itself); 0 when the sheet is not
// periodic or leaves no room.
int SeamColumns(const Surface& surface, const FlatSheet& sheet);

// The extension of a periodic sheet (PeriodicInU) by `columns` on each side
// (-1: SeamColumns; more than that is taken as that), or null when that is 0.
std::unique_ptr<const SeamExtension> ExtendAcrossSeam(const Surface& surface,
                                                      const FlatSheet& sheet, int columns = -1);

}  // namespace surfdeform
