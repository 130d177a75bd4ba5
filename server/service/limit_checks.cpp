#include "service/limit_checks.hpp"

#include <algorithm>
#include <string>
#include <variant>

#include "base/format.hpp"
#include "engine/distance/surface_distance.hpp"
#include "engine/subdivision/subdivide.hpp"
#include "service/memory_budget.hpp"

namespace surfdeform {

double FlatteningBytes(const SamplingOptions& s, const FlattenSettings& f) {
  const double samples = static_cast<double>(s.nu) * s.nv;
  const double per_sample =
      kSheetBytesPerSample + kSheetBytesPerExtraPair * ExtraPairsPerSample(f.range);
  // The distance lattice, and the paths kept for the next edit, grow with
  // the lattice factor's square and with it (up to 16): what they take past
  // the automatic factor's, which the per-sample figure was measured at.
  const double lattice = static_cast<double>(DistanceLatticePoints(s.nu, s.nv, f.lattice_factor)) -
                         static_cast<double>(DistanceLatticePoints(s.nu, s.nv, 0));
  const double pairs = samples * 2.0 * f.range * (f.range + 1.0);
  const double path_points =
      DistanceLatticeFactor(s.nu, s.nv, f.lattice_factor) - DistanceLatticeFactor(s.nu, s.nv, 0);
  return per_sample * samples +
         std::max(0.0, kLatticeBytesPerPoint * lattice + kPathBytesPerPoint * pairs * path_points);
}

Status CheckGrid(const ServiceLimits& limits, const SamplingOptions& s, const FlattenSettings& f) {
  const int side = std::max(s.nu, s.nv);
  if (side > limits.max_grid_side) {
    return Status::LimitExceeded("the sampling grid is " + std::to_string(s.nu) + " x " +
                                     std::to_string(s.nv) + "; this server flattens at most " +
                                     std::to_string(limits.max_grid_side) + " samples per side",
                                 s.nu >= s.nv ? "sampling.nu" : "sampling.nv", limits.max_grid_side,
                                 side);
  }
  // The field to change: the sampling, unless a lattice factor asked for
  // makes it too large.
  const double bytes = FlatteningBytes(s, f);
  FlattenSettings automatic = f;
  automatic.lattice_factor = 0;
  const bool lattice = f.lattice_factor > 0 && FlatteningBytes(s, automatic) <=
                                                   static_cast<double>(limits.request_memory_bytes);
  return CheckMemory(bytes, limits.request_memory_bytes,
                     "flattening a " + std::to_string(s.nu) + " x " + std::to_string(s.nv) +
                         " grid at range " + std::to_string(f.range) + " with lattice factor " +
                         std::to_string(DistanceLatticeFactor(s.nu, s.nv, f.lattice_factor)),
                     lattice ? "flatten.lattice_factor" : "sampling");
}

namespace {

// The copies of the sheet a frame's map holds: 1; 3 where some key closes
// in u or v (the map continues it a period past the seam each way); 9 past
// both seams (a whole torus). Its frames' maps take that much more memory.
int SheetCopies(const proto::AnimationRequest& request) {
  int copies = 1;
  for (const Keyframe& key : request.animation.keyframes) {
    copies = std::max(copies, (ClosesInU(key.surface) ? 3 : 1) * (ClosesInV(key.surface) ? 3 : 1));
  }
  return copies;
}

// Whether `error` is the engine stopping at `bound`, a limit this request's
// budget lowered below the configured one: then the caller says so in the
// budget's terms.
bool AtBudgetBound(const Status& error, size_t bound, size_t configured) {
  return error.code() == ErrorCode::kLimitExceeded && bound < configured && error.has_limit() &&
         error.limit() == static_cast<double>(bound);
}

}  // namespace

double AnimationSheetsBytes(const proto::AnimationRequest& request) {
  const SamplingOptions& s = request.sampling;
  const int copies = SheetCopies(request);
  const double per_frame_sample =
      (copies == 1 ? kAnimationBytesPerFrameSample
                   : kClosedAnimationBytesPerFrameSample * copies / 3) +
      kAnimationBytesPerFrameExtraPair * ExtraPairsPerSample(request.flatten.range);
  // Frame after frame, one flattening's own memory (its lattice and paths)
  // at a time, beside every frame's sheets and maps.
  return per_frame_sample * request.animation.frames * s.nu * s.nv +
         FlatteningBytes(s, request.flatten);
}

Status CheckFrames(const ServiceLimits& limits, const proto::AnimationRequest& request) {
  SURFDEFORM_RETURN_IF_ERROR(CheckGrid(limits, request.sampling, request.flatten));
  const int frames = request.animation.frames;
  const int limit = limits.max_animation_frames;
  if (frames > limit) {
    return Status::LimitExceeded("this server animates at most " + std::to_string(limit) +
                                     " frames, asked for " + std::to_string(frames),
                                 "animation.frames", limit, frames);
  }
  const SamplingOptions& s = request.sampling;
  return CheckMemory(AnimationSheetsBytes(request), limits.request_memory_bytes,
                     "flattening " + std::to_string(frames) + " frames of " + std::to_string(s.nu) +
                         " x " + std::to_string(s.nv),
                     "animation.frames");
}

Status CheckFrameVertices(const ServiceLimits& limits, size_t frames, size_t vertices) {
  if (frames * vertices <= limits.max_animation_frame_vertices) return Status::Ok();
  return Status::LimitExceeded(std::to_string(frames) + " frames of " + std::to_string(vertices) +
                                   " vertices are more than this server animates in one request (" +
                                   std::to_string(limits.max_animation_frame_vertices) +
                                   " frame vertices); ask for fewer frames or a smaller model",
                               "animation.frames",
                               static_cast<double>(limits.max_animation_frame_vertices),
                               static_cast<double>(frames * vertices));
}

Result<int> FieldSideOf(const ServiceLimits& limits, std::string_view text, const char* field,
                        int default_side) {
  if (text.empty()) return default_side;
  long long n = 0;
  for (char c : text) {
    if (c < '0' || c > '9' || text.size() > 9) {
      return Status(ErrorCode::kMalformed,
                    "must be a whole number of lattice points per side, got \"" +
                        std::string(text.substr(0, 32)) + "\"",
                    field);
    }
    n = 10 * n + (c - '0');
  }
  if (n > limits.max_field_side) {
    return Status::LimitExceeded("this server samples fields of at most " +
                                     std::to_string(limits.max_field_side) +
                                     " lattice points per side, asked for " + std::to_string(n),
                                 field, limits.max_field_side, static_cast<double>(n));
  }
  return static_cast<int>(n);
}

JsonLimits JsonLimitsOf(const ServiceLimits& limits) {
  JsonLimits l;
  l.max_depth = limits.max_json_depth;
  l.max_elements = limits.max_json_elements;
  l.max_string_bytes = limits.max_json_string_bytes;
  return l;
}

ImportLimits ImportLimitsOf(const ServiceLimits& limits) {
  ImportLimits l;
  l.max_bytes = limits.max_body_bytes;
  l.max_vertices = limits.max_vertices;
  l.max_triangles = limits.max_triangles;
  l.max_json_depth = 2 * limits.max_json_depth;
  l.max_image_bytes = limits.max_body_bytes;  // they travel to the output as they came
  return l;
}

size_t MaxMapOutputPoints(const ServiceLimits& limits) {
  return CountWithin(limits.request_memory_bytes, kMapBytesPerOutputPoint, kMaxMapOutputPoints);
}

size_t MaxOutputVertices(const ServiceLimits& limits) {
  return CountWithin(limits.request_memory_bytes, kSubdivisionBytesPerVertex,
                     limits.max_output_vertices);
}

size_t MaxSubdivisionCrossings(const ServiceLimits& limits) {
  return std::max<size_t>(1, CountWithin(limits.request_memory_bytes, kSubdivisionBytesPerCrossing,
                                         SubdivisionOptions{}.max_crossings));
}

Status CheckSurfaceMesh(const ServiceLimits& limits, size_t vertices) {
  return CheckMemory(
      kMeshSheetBytesPerVertex * static_cast<double>(vertices), limits.request_memory_bytes,
      "flattening a mesh of " + std::to_string(vertices) + " vertices", "surface.model_id");
}

Status CheckMeshFrames(const ServiceLimits& limits, size_t frames, size_t keys, size_t vertices) {
  const double v = static_cast<double>(vertices);
  const double for_frames = kMeshAnimationBytesPerFrameVertex * static_cast<double>(frames) * v;
  const double for_keys = kMeshKeyBytesPerVertex * static_cast<double>(keys) * v;
  return CheckMemory(
      kMeshSheetBytesPerVertex * v + for_frames + for_keys, limits.request_memory_bytes,
      "flattening " + std::to_string(frames) + " frames of a mesh of " + std::to_string(vertices) +
          " vertices between " + std::to_string(keys) + " keyframes",
      for_keys > for_frames ? "animation.keyframes" : "animation.frames");
}

size_t MaxSurfaceMeshPairs(const ServiceLimits& limits, size_t vertices) {
  const double start = kMeshSheetBytesPerVertex * static_cast<double>(vertices);
  const double left = std::max(0.0, static_cast<double>(limits.request_memory_bytes) - start);
  return std::max<size_t>(1, CountWithin(static_cast<size_t>(left), kMeshSheetBytesPerPair,
                                         limits.max_surface_mesh_pairs));
}

Status SurfaceMeshPairsError(const ServiceLimits& limits, size_t vertices, Status error) {
  const size_t bound = MaxSurfaceMeshPairs(limits, vertices);
  if (!AtBudgetBound(error, bound, limits.max_surface_mesh_pairs)) return error;
  return Status::LimitExceeded(
      Format("flattening this mesh of %zu vertices would take more than this server's memory "
             "budget of %.0f MiB per request: it has more than the %zu vertex pairs within its "
             "rings that fit beside its vertices (%.0f B a vertex, %.0f B a pair); decimate the "
             "mesh, or use a smaller flatten.range",
             vertices, static_cast<double>(limits.request_memory_bytes) / (1024.0 * 1024.0), bound,
             kMeshSheetBytesPerVertex, kMeshSheetBytesPerPair),
      error.field(), error.limit(), error.actual());
}

size_t MaxAnimationOutputVertices(const ServiceLimits& limits, size_t frames, int threads) {
  frames = std::max<size_t>(frames, 1);
  const size_t by_count = limits.max_animation_frame_vertices / frames;
  // The refined model (as a deformation's output), the pass's subdivisions
  // of it (a frame a thread) and every frame's share, held at once.
  const size_t at_once = std::min(frames, static_cast<size_t>(std::max(threads, 1)));
  const size_t by_memory = CountWithin(
      limits.request_memory_bytes,
      kSubdivisionBytesPerVertex + kSubdivisionPassBytesPerVertex * static_cast<double>(at_once) +
          kAnimationBytesPerFrameVertex * static_cast<double>(frames),
      std::min(by_count, limits.max_output_vertices));
  return std::max<size_t>(1, by_memory);
}

Status AnimationSubdivisionError(const ServiceLimits& limits, size_t frames, int threads,
                                 Status error) {
  const size_t bound = MaxAnimationOutputVertices(limits, frames, threads);
  if (!AtBudgetBound(error, bound, MaxOutputVertices(limits))) return error;
  return Status::LimitExceeded(
      error.message() + "; each of the animation's " + std::to_string(frames) +
          " frames holds the refined model, which is why the limit is " + std::to_string(bound) +
          " (" + std::to_string(limits.max_animation_frame_vertices) +
          " frame vertices in all, within the memory budget per request): fewer frames also "
          "help",
      error.field(), error.limit(), error.actual());
}

}  // namespace surfdeform
