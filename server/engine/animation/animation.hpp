// Animated surfaces: keyframes of one surface shape, interpolated in time, and
// the sequence of flat sheets they give (the paper's Figures 12-13: a model
// swimming along a moving surface).
//
// Keyframes are surfaces of one kind and shape (the same degrees, counts of
// control points and knots, grid size; for analytic kinds the same fields).
// Every number of the surface is interpolated between them: kLinear, or
// kCubic (cubic Hermite with Catmull-Rom tangents, finite differences of the
// neighbouring keys over their time span; one-sided at the ends: C1 through
// the keys, and linear for two keys). A single keyframe must be a wave, whose
// time then advances by 1 / fps per frame. Frames are sampled evenly over the
// key times: frame k of n at t_first + k (t_last - t_first) / (n - 1).
//
// Flattening the sequence (FlattenAnimation): the surface distances of every
// kPathAnchorEvery-th frame (an anchor) are measured afresh, and those of the
// frames between two anchors along the blend of the paths the anchors
// followed (the geodesics move smoothly with the surface; no relaxation is
// needed). The frames' distances do not depend on one another's sheets, so
// worker threads measure them ahead, a frame each at a time, while the
// calling thread solves the frames in order with one Flattener (the factored
// Laplacian is shared) and measures too whenever the next frame's distances
// are not ready. Each frame starts from the previous frames' sheets
// carried on, 3 X[k-1] - 3 X[k-2] + X[k-3] (warm start; fewer sheets on the
// second and third frames), except frames that land exactly on a key, which
// start as the key alone would, so that their sheets are bit for bit the
// static surface's (and so are deformations through them). Every
// sheet is in the canonical frame of flatten.hpp (sample (0, 0) at the
// origin, its first grid edge along +X), which moves continuously with the
// surface: nothing jumps or spins between frames. A model is placed on every
// frame's sheet as on a static one, at one scale (placement.hpp,
// ComputeFramePlacements): "center" stays on the surface point (1/2, 1/2).
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/animation/animation_spec.hpp"
#include "engine/flatten/flatten.hpp"
#include "engine/surface/sample_grid.hpp"
#include "engine/surface/surface.hpp"
#include "engine/surface/surface_spec.hpp"

namespace surfdeform {

// The time of frame k (the wave's time for a single key).
double FrameTime(const AnimationSpec& spec, int frame);

// The surface of frame k, every number interpolated. Only for a valid spec.
SurfaceSpec SurfaceAtFrame(const AnimationSpec& spec, int frame);

// What one frame's flattening did.
struct FrameFlattening {
  double time = 0.0;
  bool warm = false;     // started from the previous frame's sheet
  int reused_paths = 0;  // distances measured along the anchors' paths (0 on an anchor)
  FlattenQuality quality;
};

// Every this many frames (and on the last frame and the keys), a frame's
// distances are measured afresh: an anchor. The frames between are measured
// along the blend of the two anchors' paths.
inline constexpr int kPathAnchorEvery = 8;

struct AnimatedSheets {
  std::vector<std::unique_ptr<const Surface>> surfaces;  // per frame
  std::vector<FlatSheet> sheets;                         // per frame, canonical frame
  std::vector<FrameFlattening> frames;
  double total_ms = 0.0;
};

// For the frame loops: an error of frame k, prefixed with the frame and its
// time; a deadline is the animation's (its budget and the time spent on all
// frames so far).
Status AnimationFrameError(const AnimationSpec& spec, int frame, const Status& s, double budget_ms,
                           double spent_ms);
// What is left of the animation's budget, into o->time_budget_ms for the
// next step after `done` frames; kDeadlineExceeded once it is spent. No
// budget (0): no change.
Status AnimationBudgetLeft(const AnimationSpec& spec, int done, double budget_ms, double spent_ms,
                           FlattenOptions* o);

// The last layouts of one size (newest first, one to three) carried on to
// the next frame by the polynomial through them: X[k-1], 2 X[k-1] -
// X[k-2], or 3 X[k-1] - 3 X[k-2] + X[k-3].
std::vector<Vec2> CarryOn(std::span<const std::vector<Vec2>* const> newest_first);

// Called after each frame is flattened (frame index, frames in all), from the
// calling thread; for progress.
using FrameProgress = std::function<void(int, int)>;

// Flattens every frame of a valid spec, warm-started frame to frame. Errors
// are the flattening's, prefixed with the frame ("frame 12: ..."), with the
// field of the frame's surface where the surface itself is at fault.
// options.time_budget_ms bounds the whole sequence.
Result<AnimatedSheets> FlattenAnimation(const AnimationSpec& spec, const SamplingOptions& sampling,
                                        const FlattenOptions& options,
                                        const FrameProgress& progress = {});

}  // namespace surfdeform
