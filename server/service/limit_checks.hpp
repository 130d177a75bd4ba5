// A request's counts against the service's limits, before the work they
// stand for: each check names the field, the limit and the value asked for.
#pragma once

#include <cstddef>
#include <string_view>

#include "base/status.hpp"
#include "engine/surface/sample_grid.hpp"
#include "json/bounded_json.hpp"
#include "meshio/mesh_import.hpp"
#include "proto/api.hpp"
#include "proto/map_api.hpp"
#include "service/service_limits.hpp"

namespace surfdeform {

// POST /v1/surfaces/{id}/map: the input counts (published at /v1/info) and
// the points resampled polylines may have in all.
inline constexpr proto::MapLimits kMapLimits;
inline constexpr size_t kMaxMapOutputPoints = 1'000'000;

// The memory a flattening of this sampling with these settings takes, at
// most (its range's pairs, its lattice factor's lattice and paths).
double FlatteningBytes(const SamplingOptions& sampling, const FlattenSettings& flatten);

// The sampling grid's side and the memory its flattening takes
// (FlatteningBytes): past the budget, 413 naming the sampling, or the
// lattice factor where the automatic one would fit.
Status CheckGrid(const ServiceLimits& limits, const SamplingOptions& sampling,
                 const FlattenSettings& flatten);

// The memory an animation's sheets and maps take, at most: every frame's,
// and one flattening's own at a time.
double AnimationSheetsBytes(const proto::AnimationRequest& request);

// An animation's grid, its frame count, and the memory its sheets take.
Status CheckFrames(const ServiceLimits& limits, const proto::AnimationRequest& request);

// Frames times the model's vertices: checked on the input's count before any
// work, and again on the output's after the subdivision.
Status CheckFrameVertices(const ServiceLimits& limits, size_t frames, size_t vertices);

// The field's side from its query parameter `field` ("n" or "field"): the
// default when empty, kMalformed for anything but decimal digits,
// kLimitExceeded past limits.max_field_side (the engine refuses n < 2).
Result<int> FieldSideOf(const ServiceLimits& limits, std::string_view text, const char* field,
                        int default_side);

// What request JSON may hold.
JsonLimits JsonLimitsOf(const ServiceLimits& limits);

// What an import may read (a glTF's JSON nests deeper than a request's).
ImportLimits ImportLimitsOf(const ServiceLimits& limits);

// The most points a map request's polylines may be resampled to: the count
// limit, lowered to fit the request's memory budget.
size_t MaxMapOutputPoints(const ServiceLimits& limits);

// The most vertices a subdivision may produce: the output limit, lowered to
// fit the request's memory budget.
size_t MaxOutputVertices(const ServiceLimits& limits);

// The memory a surface given as a mesh of `vertices` takes before its pairs
// are listed (its conformal start).
Status CheckSurfaceMesh(const ServiceLimits& limits, size_t vertices);

// The most vertex pairs its flattening may measure: the pair limit, lowered
// to fit what the memory budget leaves beside its vertices.
size_t MaxSurfaceMeshPairs(const ServiceLimits& limits, size_t vertices);

// A mesh flattening stopped at MaxSurfaceMeshPairs by the memory budget,
// said in its terms; any other error as it is.
Status SurfaceMeshPairsError(const ServiceLimits& limits, size_t vertices, Status error);

// An animation of `frames` frames whose `keys` keyframes are meshes of
// `vertices` vertices: every frame's flat mesh and every key's positions,
// beside one flattening's work. The field is animation.keyframes when the
// keys weigh more than the frames, else animation.frames.
Status CheckMeshFrames(const ServiceLimits& limits, size_t frames, size_t keys, size_t vertices);

// The crossings of a model's edges with the sheet's grid lines that the
// subdivision may keep to measure, within the memory budget.
size_t MaxSubdivisionCrossings(const ServiceLimits& limits);

// The same for an animation's model, which every one of its `frames` holds:
// also within the frame vertices' limit, and the memory budget holding at
// once the refined model (kSubdivisionBytesPerVertex), the refinement pass's
// subdivision of it for each frame measured at once, one per thread of the
// `threads` the request runs on (kSubdivisionPassBytesPerVertex), and every
// frame's share of it (kAnimationBytesPerFrameVertex). Bounded before the
// refinement, so that a refinement the frames cannot hold stops where it
// passes the bound, not after it.
size_t MaxAnimationOutputVertices(const ServiceLimits& limits, size_t frames, int threads);

// An animation's subdivision stopped at MaxAnimationOutputVertices, said in
// the animation's terms; any other error as it is.
Status AnimationSubdivisionError(const ServiceLimits& limits, size_t frames, int threads,
                                 Status error);

}  // namespace surfdeform
