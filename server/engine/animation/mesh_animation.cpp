#include "engine/animation/mesh_animation.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <utility>

#include "engine/common/disk_mesh.hpp"
#include "engine/common/elapsed.hpp"
#include "engine/flatten/mesh_flatten.hpp"

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

// A triangle of an interpolated frame whose area collapsed (below what
// MakeDiskMesh refuses in a key): kDegenerate naming it.
Status CheckFrameTriangles(const DiskMesh& mesh) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = (hi - lo).norm();
  const int f = CollapsedTriangle(mesh, DiskMeshOptions{}.min_area * diagonal * diagonal);
  if (f < 0) return Status::Ok();
  return Degenerate("triangle " + std::to_string(f) +
                        " collapses to zero area between the keyframes around this frame: add "
                        "a keyframe between them, or interpolate \"linear\"",
                    "keyframes");
}

// The last (up to three) frames' flat meshes carried on to the next frame
// (CarryOn), into *carried; null before the second frame.
const std::vector<Vec2>* Carried(const AnimatedSheets& done, std::vector<Vec2>* carried) {
  const size_t history = std::min<size_t>(3, done.surfaces.size());
  if (history < 2) return nullptr;
  const std::vector<Vec2>* last[3] = {};
  for (size_t h = 0; h < history; ++h) {
    last[h] = &done.surfaces[done.surfaces.size() - 1 - h]->flat_mesh()->flat;
  }
  *carried = CarryOn(std::span(last, history));
  return carried;
}

}  // namespace

Result<AnimatedSheets> FlattenMeshAnimation(const AnimationSpec& spec,
                                            const SamplingOptions& sampling,
                                            const FlattenOptions& options,
                                            const FrameProgress& progress,
                                            const std::function<MeshSpec(int)>& frame_mesh) {
  const auto t0 = Clock::now();
  AnimatedSheets out;
  out.surfaces.reserve(spec.frames);
  out.sheets.reserve(spec.frames);
  out.frames.reserve(spec.frames);
  MeshFlattener flattener(options);  // the pairs and factor of frame 0 serve all
  Flattener sampler(options);        // each frame's sheet sampled on its flat mesh
  const std::vector<Vec2>* previous = nullptr;
  std::vector<Vec2> carried;
  for (int k = 0; k < spec.frames; ++k) {
    auto fail = [&](const Status& s) {
      return AnimationFrameError(spec, k, s, options.time_budget_ms, MsSince(t0));
    };
    FlattenOptions o = options;
    SURFDEFORM_RETURN_IF_ERROR(
        AnimationBudgetLeft(spec, k, options.time_budget_ms, MsSince(t0), &o));
    MeshSpec mesh = frame_mesh(k);
    if (mesh.disk == nullptr) {
      return fail(Status(ErrorCode::kInternal, "the frame's mesh was not resolved"));
    }
    if (k > 0) {
      if (Status s = CheckFrameTriangles(*mesh.disk); !s.ok()) return fail(s);
    }
    flattener.set_options(o);
    // The solve starts from the last sheets carried on (as a parametric
    // animation's frames do: 2 X[k-1] - X[k-2], or 3 X[k-1] - 3 X[k-2] +
    // X[k-3]); the distances are measured along the last sheet.
    const std::vector<Vec2>* guess = Carried(out, &carried);
    auto flat = flattener.Flatten(*mesh.disk, previous, guess);
    if (!flat.ok()) return fail(flat.status());
    FrameFlattening f;
    f.time = FrameTime(spec, k);
    f.warm = previous != nullptr;
    f.quality = flat->quality;
    mesh.flattened = std::make_shared<const FlatMesh>(std::move(*flat));
    mesh.disk = nullptr;  // the flat mesh holds the frame's vertices
    auto surface = MakeSurface(SurfaceSpec(mesh));
    if (!surface.ok()) return fail(surface.status());
    sampler.set_options(o);
    auto sheet = sampler.Flatten(**surface, sampling);
    if (!sheet.ok()) return fail(sheet.status());
    previous = &mesh.flattened->flat;
    out.surfaces.push_back(std::move(*surface));
    out.sheets.push_back(std::move(*sheet));
    out.frames.push_back(f);
    if (progress) progress(k, spec.frames);
  }
  out.total_ms = MsSince(t0);
  return out;
}

}  // namespace surfdeform
