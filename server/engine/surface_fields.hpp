// Every number of a surface description with its field: one walk over a
// SurfaceSpec that animations interpolate by (every number, in a fixed
// order) and MakeSurface bounds (each by the JSON path of its field).
#pragma once

#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "engine/surface_spec.hpp"

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

// Every number of a spec, in a fixed order: f(name, value), where name() gives
// its field, the JSON path below the surface ("radius",
// "control_points[3][1]"), built only when asked for. Spec: SurfaceSpec (f
// takes double&) or const SurfaceSpec (f takes const double&).
template <typename Spec, typename F>
void WalkNumbers(Spec& spec, F&& f) {
  static_assert(std::is_same_v<std::remove_const_t<Spec>, SurfaceSpec>);
  using surface_fields::WalkFrame;
  using surface_fields::WalkList;
  using surface_fields::WalkPoints;
  auto scalar = [&f](const char* name, auto& v) { f([name] { return std::string(name); }, v); };
  std::visit(
      [&](auto& s) {
        using T = std::remove_cv_t<std::remove_reference_t<decltype(s)>>;
        if constexpr (std::is_same_v<T, BezierSpec>) {
          WalkPoints("control_points", s.control_points, f);
        } else if constexpr (std::is_same_v<T, BSplineSpec>) {
          WalkPoints("control_points", s.control_points, f);
          WalkList("knots_u", s.knots_u, f);
          WalkList("knots_v", s.knots_v, f);
          WalkList("weights", s.weights, f);
        } else if constexpr (std::is_same_v<T, CylinderSpec>) {
          scalar("radius", s.radius);
          scalar("height", s.height);
          scalar("angle_deg", s.angle_deg);
          WalkFrame(s.frame, f);
        } else if constexpr (std::is_same_v<T, ConeSpec>) {
          scalar("radius_bottom", s.radius_bottom);
          scalar("radius_top", s.radius_top);
          scalar("height", s.height);
          scalar("angle_deg", s.angle_deg);
          WalkFrame(s.frame, f);
        } else if constexpr (std::is_same_v<T, SphereSpec>) {
          scalar("radius", s.radius);
          scalar("lon_min_deg", s.lon_min_deg);
          scalar("lon_max_deg", s.lon_max_deg);
          scalar("lat_min_deg", s.lat_min_deg);
          scalar("lat_max_deg", s.lat_max_deg);
          WalkFrame(s.frame, f);
        } else if constexpr (std::is_same_v<T, TorusSpec>) {
          scalar("major_radius", s.major_radius);
          scalar("minor_radius", s.minor_radius);
          scalar("u_min_deg", s.u_min_deg);
          scalar("u_max_deg", s.u_max_deg);
          scalar("v_min_deg", s.v_min_deg);
          scalar("v_max_deg", s.v_max_deg);
          WalkFrame(s.frame, f);
        } else if constexpr (std::is_same_v<T, WaveSpec>) {
          scalar("length", s.length);
          scalar("width", s.width);
          scalar("amplitude", s.amplitude);
          scalar("wavelength", s.wavelength);
          scalar("speed", s.speed);
          scalar("time", s.time);
          WalkFrame(s.frame, f);
        } else if constexpr (std::is_same_v<T, GridSpec>) {
          WalkPoints("points", s.points, f);
        }
      },
      spec);
}

}  // namespace surfdeform
