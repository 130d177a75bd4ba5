// One description of each surface kind's fields (VisitFields), and the walk
// over its numbers that animations interpolate by (every number, in a fixed
// order) and MakeSurface bounds (each by the JSON path of its field).
#pragma once

#include <concepts>
#include <cstddef>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "engine/surface/surface_spec.hpp"

namespace surfdeform {
namespace surface_fields {

// FrameT, Points, Values: the types as they are, or const.
template <typename FrameT, typename F>
void WalkFrame(FrameT& frame, F&& f) {
  const char* axes[] = {"origin", "x_axis", "z_axis"};
  decltype(&frame.origin) values[] = {&frame.origin, &frame.x_axis, &frame.z_axis};
  for (int a = 0; a < 3; ++a) {
    for (int c = 0; c < 3; ++c) {
      f([&] { return std::string("frame.") + axes[a] + "[" + std::to_string(c) + "]"; },
        (*values[a])[c]);
    }
  }
}

template <typename Points, typename F>
void WalkPoints(const char* name, Points& points, F&& f) {
  for (size_t k = 0; k < points.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      f(
          [&] {
            return std::string(name) + "[" + std::to_string(k) + "][" + std::to_string(c) + "]";
          },
          points[k][c]);
    }
  }
}

template <typename Values, typename F>
void WalkList(const char* name, Values& values, F&& f) {
  for (size_t k = 0; k < values.size(); ++k) {
    f([&] { return std::string(name) + "[" + std::to_string(k) + "]"; }, values[k]);
  }
}

}  // namespace surface_fields

// One description of each kind's fields, in the API's order: VisitFields(s,
// v) calls, for every field of a spec of that kind (s const or not):
//   v.Integer(name, int&)                  a degree or a count
//   v.Number(name, double&)
//   v.Numbers(name, std::vector<double>&)  knots, weights
//   v.Points(name, std::vector<Vec3>&)     control points, grid points
//   v.Flag(name, bool&)                    a switch (written only when set)
//   v.Placement(name, Frame&)              the frame an analytic kind stands in
//   v.Text(name, std::string&)             an id
// Parsing and writing a surface (proto/surface_json.hpp), the numbers that
// animations interpolate and MakeSurface bounds (WalkNumbers), and the
// store's byte estimate (CountNumbers) all go through it: a field added here
// is read, written, interpolated, bounded and counted. A kind of the
// engine's own (a test's) joins by a VisitFields beside it.
template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, BezierSpec>
void VisitFields(S& s, V&& v) {
  v.Integer("degree_u", s.degree_u);
  v.Integer("degree_v", s.degree_v);
  v.Points("control_points", s.control_points);
}

template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, BSplineSpec>
void VisitFields(S& s, V&& v) {
  v.Integer("degree_u", s.degree_u);
  v.Integer("degree_v", s.degree_v);
  v.Integer("count_u", s.count_u);
  v.Integer("count_v", s.count_v);
  v.Points("control_points", s.control_points);
  v.Numbers("knots_u", s.knots_u);
  v.Numbers("knots_v", s.knots_v);
  if (s.rational) v.Numbers("weights", s.weights);  // "nurbs" only
  v.Flag("periodic_u", s.periodic_u);
  v.Flag("periodic_v", s.periodic_v);
}

template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, CylinderSpec>
void VisitFields(S& s, V&& v) {
  v.Number("radius", s.radius);
  v.Number("height", s.height);
  v.Number("angle_deg", s.angle_deg);
  v.Placement("frame", s.frame);
}

template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, ConeSpec>
void VisitFields(S& s, V&& v) {
  v.Number("radius_bottom", s.radius_bottom);
  v.Number("radius_top", s.radius_top);
  v.Number("height", s.height);
  v.Number("angle_deg", s.angle_deg);
  v.Placement("frame", s.frame);
}

template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, SphereSpec>
void VisitFields(S& s, V&& v) {
  v.Number("radius", s.radius);
  v.Number("lon_min_deg", s.lon_min_deg);
  v.Number("lon_max_deg", s.lon_max_deg);
  v.Number("lat_min_deg", s.lat_min_deg);
  v.Number("lat_max_deg", s.lat_max_deg);
  v.Placement("frame", s.frame);
}

template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, TorusSpec>
void VisitFields(S& s, V&& v) {
  v.Number("major_radius", s.major_radius);
  v.Number("minor_radius", s.minor_radius);
  v.Number("u_min_deg", s.u_min_deg);
  v.Number("u_max_deg", s.u_max_deg);
  v.Number("v_min_deg", s.v_min_deg);
  v.Number("v_max_deg", s.v_max_deg);
  v.Placement("frame", s.frame);
}

template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, WaveSpec>
void VisitFields(S& s, V&& v) {
  v.Number("length", s.length);
  v.Number("width", s.width);
  v.Number("amplitude", s.amplitude);
  v.Number("wavelength", s.wavelength);
  v.Number("speed", s.speed);
  v.Number("time", s.time);
  v.Placement("frame", s.frame);
}

template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, GridSpec>
void VisitFields(S& s, V&& v) {
  v.Integer("nu", s.nu);
  v.Integer("nv", s.nv);
  v.Points("points", s.points);
  v.Flag("periodic_u", s.periodic_u);
  v.Flag("periodic_v", s.periodic_v);
}

// (A mesh's vertices are its model's, by id: no numbers of its own here.)
template <typename S, typename V>
requires std::same_as<std::remove_const_t<S>, MeshSpec>
void VisitFields(S& s, V&& v) { v.Text("model_id", s.model_id); }

namespace surface_fields {

// The numbers of VisitFields, each with its JSON path: for WalkFields.
template <typename F>
struct NumberWalk {
  F& f;
  template <typename I>
  void Integer(const char*, I&) {}
  template <typename B>
  void Flag(const char*, B&) {}
  template <typename T>
  void Text(const char*, T&) {}
  template <typename D>
  void Number(const char* name, D& v) {
    f([name] { return std::string(name); }, v);
  }
  template <typename L>
  void Numbers(const char* name, L& values) {
    WalkList(name, values, f);
  }
  template <typename P>
  void Points(const char* name, P& points) {
    WalkPoints(name, points, f);
  }
  template <typename R>
  void Placement(const char*, R& frame) {
    WalkFrame(frame, f);
  }
};

}  // namespace surface_fields

// Every number of one kind's spec `s` (const or not), in VisitFields' order:
// f(name, value), where name() gives its field, the JSON path below the
// surface ("radius", "control_points[3][1]"), built only when asked for.
template <typename S, typename F>
void WalkFields(S& s, F&& f) {
  VisitFields(s, surface_fields::NumberWalk<F>{f});
}

// The same over a SurfaceSpec (f takes double&) or a const SurfaceSpec (f
// takes const double&).
template <typename Spec, typename F>
void WalkNumbers(Spec& spec, F&& f) {
  static_assert(std::is_same_v<std::remove_const_t<Spec>, SurfaceSpec>);
  std::visit([&](auto& s) { WalkFields(s, f); }, spec);
}

// How many numbers a spec holds (the store's byte estimate counts them).
template <typename Spec>
size_t CountNumbers(const Spec& spec) {
  size_t n = 0;
  WalkNumbers(spec, [&n](const auto&, const double&) { ++n; });
  return n;
}

}  // namespace surfdeform
