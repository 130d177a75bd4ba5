// An animated surface as a request gives it ("animation" of POST
// /v1/animate): keyframes, interpolation, frames and rate. Plain vocabulary,
// which the API's request types (proto/) share with the engine
// (animation.hpp interpolates and flattens it).
#pragma once

#include <vector>

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/surface/surface_spec.hpp"

namespace surfdeform {

enum class Interpolation { kLinear, kCubic };
inline constexpr EnumEntry<Interpolation> kInterpolations[] = {
    {Interpolation::kLinear, "linear", "straight lines between the keys"},
    {Interpolation::kCubic, "cubic",
     "cubic Hermite with Catmull-Rom tangents: C1 through the keys (the default)"},
};

struct Keyframe {
  double time = 0.0;
  SurfaceSpec surface;
};

struct AnimationSpec {
  std::vector<Keyframe> keyframes;  // in increasing time
  Interpolation interpolation = Interpolation::kCubic;
  int frames = 60;    // 1 .. the caller's limit
  double fps = 30.0;  // playback rate; a single (wave) key also advances by 1 / fps per frame
};

// Frame rates and key times an animation may have: every frame's time and
// its time in the GLB (float seconds, strictly increasing) stay finite.
inline constexpr double kMinFps = 1e-3;
inline constexpr double kMaxFps = 1000.0;
inline constexpr double kMaxKeyTime = 1e9;  // seconds, either sign

// Keyframes: at least one, times within +-kMaxKeyTime and increasing, all of
// one kind and shape (a single one must be a wave; meshes, resolved into
// MeshSpec::disk, with the same vertices and triangles); frames from 1 to
// max_frames; fps from kMinFps to kMaxFps. Errors name the offending key and
// field ("keyframes[2].surface.degree_u"): kInvalidArgument, or
// kLimitExceeded for too many frames.
Status ValidateAnimation(const AnimationSpec& spec, int max_frames);

}  // namespace surfdeform
