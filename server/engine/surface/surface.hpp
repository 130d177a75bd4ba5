// Parametric surfaces S(u, v), (u, v) in [0, 1]^2, with exact derivatives.
//
// Conventions (docs/ARCHITECTURE.md): u runs along the first index of a control or
// sample grid, v along the second; grids are stored u-fastest
// (points[i + nu * j]). The unit normal is N = Su x Sv / |Su x Sv|.
//
// Evaluation outside [0, 1]^2 is allowed and continues the surface smoothly
// (analytic formulas, or the polynomial of the end span of a spline); the
// distance computation uses it to follow geodesics that bulge past a border.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>

#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform {

struct FlatMesh;

// Position and partial derivatives at one parameter point. Derivatives beyond
// the order asked for in Surface::Evaluate are left unset (zero).
struct SurfacePoint {
  Vec3 p = Vec3::Zero();
  Vec3 su = Vec3::Zero();
  Vec3 sv = Vec3::Zero();
  Vec3 suu = Vec3::Zero();
  Vec3 suv = Vec3::Zero();
  Vec3 svv = Vec3::Zero();
};

// Unit normal Su x Sv / |Su x Sv|; zero where the normal vanishes.
inline Vec3 UnitNormal(const SurfacePoint& s) {
  const Vec3 n = s.su.cross(s.sv);
  const double len = n.norm();
  if (!(len > 0.0)) return Vec3::Zero();
  return n / len;
}

// S + h N at a surface point (its first derivatives set): the deformed
// position of a vertex at height h. NaN where the normal vanishes, for the
// caller to report (SheetMap::Position takes a zero normal there instead).
inline Vec3 OffsetAlongNormal(const SurfacePoint& s, double h) {
  const Vec3 cross = s.su.cross(s.sv);
  return s.p + h * (cross / cross.norm());
}

class Surface {
 public:
  virtual ~Surface() = default;

  // order: 0 = position only, 1 = and first derivatives, 2 = and second derivatives.
  virtual SurfacePoint Evaluate(double u, double v, int order) const = 0;

  // Evaluate at many points: out[k] = Evaluate(uv[k], order), to rounding
  // (out.size() == uv.size()). Kinds that can evaluate several points at
  // once (the bicubic Bezier patch: four to a vector) override it; the
  // per-vertex map goes through here. Deterministic: a point's result does
  // not depend on its neighbours in `uv`.
  virtual void EvaluateMany(std::span<const Vec2> uv, int order, std::span<SurfacePoint> out) const;

  // The points at uv[k] moved by h[k] along the unit normal:
  // out[k] = OffsetAlongNormal(Evaluate(uv[k], 1), h[k]), to rounding (NaN
  // where the normal vanishes), with out.size() == h.size() == uv.size().
  // What the per-vertex map needs when it carries no normals or tangents;
  // the bicubic Bezier patch computes four points to a vector and keeps
  // their derivatives in registers. Deterministic as EvaluateMany.
  virtual void OffsetMany(std::span<const Vec2> uv, std::span<const double> h,
                          std::span<Vec3> out) const;

  // The kind as named in the API: "bezier", "cylinder", ...
  virtual const char* Kind() const = 0;

  // For developable kinds with a closed-form isometric unrolling (cylinder, cone):
  // the flat position of (u, v), in surface units, in an arbitrary rigid frame.
  // std::nullopt for every other kind: they are flattened numerically.
  virtual std::optional<Vec2> ExactUnrolling(double /*u*/, double /*v*/) const {
    return std::nullopt;
  }

  // The inverse of ExactUnrolling: the parameters of a flat point in the same
  // frame (continued past [0, 1]^2 smoothly). std::nullopt where there is none.
  virtual std::optional<Vec2> InverseUnrolling(const Vec2& /*flat*/) const { return std::nullopt; }

  // Whether the surface closes in u: S(u + 1, v) = S(u, v) for every v, and
  // evaluation past [0, 1] in u goes round again (a full cylinder or cone).
  virtual bool ClosedInU() const { return false; }
  // The same in v: S(u, v + 1) = S(u, v) (a torus all round its tube).
  virtual bool ClosedInV() const { return false; }

  // Kinds whose surface covers only part of the unit square of parameters
  // (a mesh surface: its flat triangles within a box round them): how far
  // (u, v) is from that part, in the unrolling's units (0 on it), and the
  // nearest parameters on it (to `nearest`, when not null). std::nullopt for
  // the kinds defined over the whole square.
  virtual std::optional<double> DomainGap(const Vec2& /*uv*/, Vec2* /*nearest*/) const {
    return std::nullopt;
  }

  // For the same kinds: how deep (u, v) lies in that part, its distance from
  // the part's boundary in the unrolling's units (negative off it).
  virtual std::optional<double> DomainDepth(const Vec2& /*uv*/) const { return std::nullopt; }

  // A surface given as a mesh: its flattening (the mesh, the flat position
  // of every vertex and the quality), which the sheet takes as it is.
  virtual const FlatMesh* flat_mesh() const { return nullptr; }

  Vec3 Position(double u, double v) const { return Evaluate(u, v, 0).p; }
};

}  // namespace surfdeform
