// Plain descriptions of surfaces, one struct per kind, mirroring the JSON of the
// API field by field (names are the JSON names). MakeSurface validates a spec and
// builds the evaluable Surface; every rejection names the offending field.
#pragma once

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

// Placement of an analytic surface: its local frame in world space. The axes
// need not be unit length or exactly orthogonal: z_axis is normalised, x_axis is
// made orthogonal to it, y = z x x. They must not be parallel or zero.
struct Frame {
  Vec3 origin = Vec3::Zero();
  Vec3 x_axis = Vec3::UnitX();
  Vec3 z_axis = Vec3::UnitZ();
};

// Tensor-product Bezier patch, degree 1..15 in each direction;
// (degree_u + 1) * (degree_v + 1) control points, u fastest.
struct BezierSpec {
  int degree_u = 3;
  int degree_v = 3;
  std::vector<Vec3> control_points;
};

// Clamped B-spline / NURBS patch, degree 1..7 in each direction.
// count_u * count_v control points, u fastest; knots_u has count_u + degree_u + 1
// non-decreasing values with the first and last degree_u + 1 equal (clamped),
// likewise knots_v. weights: empty for a non-rational B-spline, otherwise one
// positive weight per control point (NURBS).
struct BSplineSpec {
  int degree_u = 3;
  int degree_v = 3;
  int count_u = 0;
  int count_v = 0;
  std::vector<Vec3> control_points;
  std::vector<double> knots_u;
  std::vector<double> knots_v;
  std::vector<double> weights;
  bool rational = false;  // true for kind "nurbs": weights are then required
  // The surface closes in u: S(0, v) = S(1, v), as a closed control net
  // gives (its first and last columns equal) with clamped knots, or a
  // periodic one (its last degree_u columns repeating the first) with
  // unclamped uniform knots, which are then allowed. Checked: a seam that
  // fails to meet by more than 1e-9 of the net's size is refused, saying by
  // how much. Such a surface is flattened periodic.
  bool periodic_u = false;
  bool periodic_v = false;  // the same in v (knots_v, the first and last rows)
};

// Cylinder patch: u is the angle from the frame's +X towards +Y over angle_deg,
// v the height along +Z from 0 to height. Normal points away from the axis.
struct CylinderSpec {
  double radius = 1.0;
  double height = 1.0;
  double angle_deg = 360.0;  // (0, 360]
  Frame frame;
};

// Cone patch (a truncated cone): radius_bottom at v = 0, radius_top at v = 1
// (at most one of them zero; an apex inside the sampled range has no normal),
// otherwise as the cylinder.
struct ConeSpec {
  double radius_bottom = 1.0;
  double radius_top = 0.5;
  double height = 1.0;
  double angle_deg = 360.0;
  Frame frame;
};

// Sphere patch: u is the longitude from lon_min_deg to lon_max_deg (from +X
// towards +Y), v the latitude from lat_min_deg to lat_max_deg (-90..90, +Z up).
// A patch reaching a pole has no normal there and is rejected when sampled.
struct SphereSpec {
  double radius = 1.0;
  double lon_min_deg = 0.0;
  double lon_max_deg = 90.0;
  double lat_min_deg = -45.0;
  double lat_max_deg = 45.0;
  Frame frame;
};

// Torus patch: u is the angle around the main axis (+Z) from u_min_deg to
// u_max_deg, v the angle around the tube from v_min_deg to v_max_deg (0 = outer
// equator, 90 = top). Normal points away from the tube's centre line.
struct TorusSpec {
  double major_radius = 2.0;
  double minor_radius = 0.5;
  double u_min_deg = 0.0;
  double u_max_deg = 90.0;
  double v_min_deg = -90.0;
  double v_max_deg = 90.0;
  Frame frame;
};

// Travelling-wave sheet: x = u * length, y = v * width,
// z = amplitude * sin(2 pi (x - speed * time) / wavelength).
struct WaveSpec {
  double length = 4.0;
  double width = 1.0;
  double amplitude = 0.2;
  double wavelength = 2.0;
  double speed = 1.0;  // phase speed, length units per time unit
  double time = 0.0;
  Frame frame;
};

// User-sampled grid of nu * nv points (u fastest), interpolated by a C2 bicubic
// spline with natural end conditions that passes through every point, the point
// (i, j) at (u, v) = (i / (nu - 1), j / (nv - 1)).
struct GridSpec {
  int nu = 0;
  int nv = 0;
  std::vector<Vec3> points;
  // The grid closes in u: its last column repeats its first (checked, as
  // for BSplineSpec::periodic_u), and the spline interpolates the columns
  // periodically (C2 across the seam) instead of with natural ends.
  bool periodic_u = false;
  bool periodic_v = false;  // the same in v: the last row repeats the first
};

// A surface given as a triangle mesh: an uploaded model, by id,
// which must be a disk (disk_mesh.hpp). The service resolves the id and
// flattens the mesh (`flattened`, not part of the description) before
// MakeSurface, which wraps the flattening as a MeshSurface.
struct DiskMesh;

// An animation's keyframes of this kind carry the mesh itself instead
// (`disk`, welded and checked; also resolved by the service): their frames
// interpolate its vertices and are flattened one after another.
struct MeshSpec {
  std::string model_id;
  std::shared_ptr<const FlatMesh> flattened;
  std::shared_ptr<const DiskMesh> disk;
};

using SurfaceSpec = std::variant<BezierSpec, BSplineSpec, CylinderSpec, ConeSpec, SphereSpec,
                                 TorusSpec, WaveSpec, GridSpec, MeshSpec>;

// The kinds of surface, by their names in the API (`surface.kind`): one per
// spec, but for BSplineSpec, which is "nurbs" when rational.
enum class SurfaceKind {
  kBezier,
  kBSpline,
  kNurbs,
  kCylinder,
  kCone,
  kSphere,
  kTorus,
  kWave,
  kGrid,
  kMesh
};
inline constexpr EnumEntry<SurfaceKind> kSurfaceKinds[] = {
    {SurfaceKind::kBezier, "bezier", "tensor-product Bezier patch of any degree"},
    {SurfaceKind::kBSpline, "bspline", "clamped B-spline"},
    {SurfaceKind::kNurbs, "nurbs", "clamped B-spline with weights"},
    {SurfaceKind::kCylinder, "cylinder", "cylinder patch (u: angle, v: height)"},
    {SurfaceKind::kCone, "cone", "truncated cone patch"},
    {SurfaceKind::kSphere, "sphere", "sphere patch (u: longitude, v: latitude)"},
    {SurfaceKind::kTorus, "torus", "torus patch (v around the tube)"},
    {SurfaceKind::kWave, "wave", "travelling wave sheet, with a time"},
    {SurfaceKind::kGrid, "grid", "a grid of points, interpolated smoothly"},
    {SurfaceKind::kMesh, "mesh", "an uploaded triangle mesh (model_id) that is a disk"},
};

SurfaceKind KindOf(const SurfaceSpec& spec);
inline std::string_view KindName(SurfaceKind kind) {
  return NameOf<SurfaceKind>(kSurfaceKinds, kind);
}

// The largest magnitude of any number of a surface description (sizes,
// coordinates, knots, angles, times): past it the products in the surface's
// derivatives and normals overflow double precision.
inline constexpr double kMaxSurfaceNumber = 1e15;

// Validates the spec and builds the surface. Errors: kInvalidArgument for bad
// numbers and counts (any number past kMaxSurfaceNumber among them),
// kDegenerate for a surface that cannot have a normal (zero radius,
// collapsed control grid, parallel frame axes).
Result<std::unique_ptr<Surface>> MakeSurface(const SurfaceSpec& spec);

// Whether the surface a spec describes closes in u (Surface::ClosedInU of
// the surface MakeSurface builds): a cylinder or cone of 360 degrees, a
// sphere's whole longitude, a torus whole round its axis.
bool ClosesInU(const SurfaceSpec& spec);
// The same in v (Surface::ClosedInV): a torus all round its tube, a spline
// or grid with periodic_v.
bool ClosesInV(const SurfaceSpec& spec);

}  // namespace surfdeform
