// A sheet of a surface closed in u or v, continued past its
// seams, so that a model may lie across a seam and wrap round the surface.
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
// Sheets unrolled in closed form (a full cylinder: the strip continues by
// the translation (2 pi R, 0); a full cone: the annular sector continues by
// a rotation about the apex, as far as the plane allows before the
// continued sector would meet itself), and sheets flattened periodic
// (FlatSheet::period_u, period_v: the sheet continues by translated copies,
// a period each way, in u and in v; nine copies for a whole torus).
#pragma once

#include <memory>
#include <optional>

#include "engine/flatten/flatten.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

// `given` over the parameters (u', v') in [0, 1]^2 for its
// (u, v) = (u0 + u_scale u', v0 + v_scale v'), wrapped into [0, 1) in the
// directions where it closes (Surface::ClosedInU, ClosedInV); derivatives
// scaled to match. Keeps a reference to `given`.
std::unique_ptr<const Surface> Continued(const Surface& given, double u0, double u_scale,
                                         double v0 = 0.0, double v_scale = 1.0);

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

// Whether a model on `sheet` may cross the seam of `surface` in v: the
// surface closes in v and the sheet was flattened periodic there
// (FlatSheet::period_v; a whole torus, or a tube).
bool PeriodicInV(const Surface& surface, const FlatSheet& sheet);

struct SeamExtension {
  std::unique_ptr<const Surface> surface;  // the given one over the extended columns and rows
  FlatSheet sheet;         // nu + 2 columns, nv + 2 rows, the given ones in the middle
  int columns = 0;         // added on each side in u
  int rows = 0;            // added on each side in v
  int period_columns = 0;  // columns of one period (the given nu - 1), 0 unless periodic in u
  int period_rows = 0;     // the same in v
  double u0 = 0.0;         // the given surface's u at extended u' = 0
  double u_scale = 1.0;    // d(given u)/d(extended u')
  double v0 = 0.0;         // likewise in v
  double v_scale = 1.0;

  // The given surface's parameters of extended parameters, wrapped into
  // [0, 1) in the periodic directions.
  Vec2 GivenParameters(const Vec2& extended) const;
  // The extended parameters of the given surface's (in [0, 1]: the middle copy).
  Vec2 ExtendedParameters(const Vec2& given) const;
};

// The columns the extension of a periodic sheet adds on each side: a period,
// or fewer where the plane leaves less room (a cone's sector continued past
// half a turn from its middle would meet itself); 0 when the sheet is not
// periodic or leaves no room.
int SeamColumns(const Surface& surface, const FlatSheet& sheet);

// The rows the extension adds on each side: a period where the sheet is
// periodic in v (PeriodicInV), else 0.
int SeamRows(const Surface& surface, const FlatSheet& sheet);

// The extension of a periodic sheet by `columns` on each side in u (-1:
// SeamColumns; more than that is taken as that) and SeamRows in v, or null
// when both are 0.
std::unique_ptr<const SeamExtension> ExtendAcrossSeam(const Surface& surface,
                                                      const FlatSheet& sheet, int columns = -1);

}  // namespace surfdeform
