// Laying a model on a flat sheet and carrying it onto the surface (the
// paper's section 3.2).
//
// Placement (placement.hpp): the model axis `up` becomes the surface normal,
// the model's height along it, from `anchor`, the distance h along the
// normal; its footprint (a, b) is rotated, scaled (or fitted) and centred on
// the flat sheet. Then, optionally, faces larger than the grid are refined
// where the surface bends (subdivide.hpp).
//
// Deformation of each vertex: locate its footprint (a, b) in the flat sheet
// (FlatLocator, O(1)), invert the cell's bilinear map exactly to surface
// parameters (u, v), evaluate the surface exactly there (not interpolated from
// the grid) and place the vertex at S(u, v) + h N(u, v). Normals and tangents
// follow the map's Jacobian (normals by its inverse transpose), so hard edges
// stay hard; texture coordinates, colours and groups carry over unchanged, and
// the vertex order and count are kept (with subdivision, new vertices follow
// the input's). Parallel over vertices; the result does not depend on the
// thread count.
//
// With placement.rigid, parts of the model move as rigid bodies instead
// (rigid_parts.hpp); there is nothing to subdivide then.
//
// Asked for (DeformOptions::distortion), the result's mesh also carries, per
// vertex, the distortion of the map there (distortion.hpp), and the stats
// summarise it.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/status.hpp"
#include "engine/common/flat_sheet.hpp"
#include "engine/common/mesh.hpp"
#include "engine/deform/distortion.hpp"
#include "engine/deform/rigid_parts.hpp"
#include "engine/placement/placement.hpp"
#include "engine/sheet/sheet_footprint.hpp"
#include "engine/subdivision/subdivide.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

struct DeformStats {
  size_t vertices = 0;
  size_t triangles = 0;
  size_t outside = 0;  // footprint points outside the sheet (clamped or extrapolated)
  double max_outside_distance = 0.0;  // the farthest of them from the sheet, sheet units
  double scale = 1.0;                 // the scale used (the fitted one with fit)
  UpAxis up = UpAxis::kPosZ;          // the model axis used as the normal (kAuto resolved)
  const char* up_reason = "given";    // Placement::up_reason
  int fit_frame = -1;  // an animation's frame whose sheet decided a fitted scale (-1: none)
  // A surface closed in u: how far round it the model goes, in turns (past 1
  // it lies over itself; TurnsRound). 0 on other surfaces.
  double turns = 0.0;
  double time_ms = 0.0;          // the whole call
  double subdivide_ms = 0.0;     // of which the subdivision
  SubdivisionStats subdivision;  // mode kOff when not asked for
  DistortionStats distortion;    // computed only when asked for
  RigidStats rigid;              // mode kNone unless placement.rigid
};

// What a deformation is asked for.
struct DeformOptions {
  PlacementOptions placement;
  // None unless asked for (the options' own default mode is adaptive).
  SubdivisionOptions subdivision = SubdivisionIn(SubdivisionMode::kOff);
  bool distortion = false;  // Mesh::distortion per output vertex, and its stats
  // Only the geometry the map computes (positions, normals, tangents, and the
  // distortion when asked for) is written: for callers that keep the rest
  // (triangles, texture coordinates, colours, groups) from the model, as an
  // animation's frames do (DeformPrepared).
  bool geometry_only = false;
};

struct DeformResult;

// What deformations of one model (its positions and triangles) on one sheet
// with one placement learn, for the next such deformation to recall: the
// service keeps them for models that come back (service/placement_memo). A
// recalled value must be what the deformation would compute itself, so the
// output is the same bits either way. Every method has a default that
// recalls nothing.
class DeformMemo {
 public:
  virtual ~DeformMemo() = default;
  // The placement computed before for the same positions, sheet and
  // placement options.
  virtual std::optional<Placement> RecallPlacement() const { return std::nullopt; }
  // Where the input vertices lie on the sheet (DeformResult::footprint).
  // Ignored when its size is not the input's vertex count.
  virtual std::shared_ptr<const SheetFootprint> RecallFootprint() const { return nullptr; }
  // A subdivision of the same mesh with the same options (but the thread
  // count and the time budget) added nothing, with these statistics
  // (DeformResult::unrefined): it is not run again, and the mesh is mapped
  // as without it.
  virtual std::optional<SubdivisionStats> RecallUnrefined() const { return std::nullopt; }
  // Record the footprint in DeformResult::footprint when none is recalled
  // (none is recorded on sheets unrolled in closed form, which locate no
  // cell).
  virtual bool WantsFootprint() const { return false; }
  // Called with a deformation's result before it is returned.
  virtual void Learn(DeformResult& /*result*/) {}
};

struct DeformResult {
  Mesh mesh;
  DeformStats stats;
  Placement placement;       // the one used (Deform only)
  SheetFootprint footprint;  // with DeformMemo::WantsFootprint (Deform only)
  // A subdivision was asked for and added nothing (or, with
  // DeformMemo::RecallUnrefined, was known to): stats.subdivision says why.
  bool unrefined = false;
};

// Deforms `mesh` through `map` (SheetMap(surface, sheet); a stored surface
// keeps its map, with its locator and its continuation past a seam, for
// every request), refined first when options.subdivision asks, with what
// `memo` recalls and teaches it (may be null). Errors: kInvalidArgument for
// bad options or a malformed mesh; kDegenerate for a footprint that cannot be
// fitted or a deformation that would produce non-finite values;
// kOutsideSheet, with the count and the worst distance, when the footprint
// leaves the sheet and outside = kError; kLimitExceeded when the refined mesh
// would exceed the subdivision's size limits.
Result<DeformResult> Deform(const SheetMap& map, Mesh mesh, const DeformOptions& options,
                            DeformMemo* memo = nullptr);

// One model deformed through several sheets of one grid (the frames of an
// animation): placed on every sheet as a static deformation on that sheet
// would be (ComputeFramePlacements: the frames on keys are the static
// deformations on the keys), at one scale, and refined once, so that every
// frame has one topology (the input's vertices first, in order) and meets the
// subdivision's tolerance.
struct PreparedModel {
  Mesh mesh;  // model coordinates, refined
  // (a, b, h) per vertex of mesh on the first sheet; empty: placed on the
  // fly. The placements differ only in their target, so frame k's are these
  // moved by placements[k].target - placements[0].target.
  std::vector<Vec3> placed;
  std::vector<Placement> placements;  // per sheet
  int fit_frame = -1;                 // with fit: the frame whose sheet decided the scale
  size_t input_vertices = 0;          // the input's, before any refinement
  bool need_frame = false;            // normals or tangents to carry
  // The topology's: counts before and after; the largest deviation measured
  // over every frame in the last pass, and the points measured there.
  SubdivisionStats subdivision;
  double subdivide_ms = 0.0;
  int subdivision_passes = 0;  // over every map (a pass that adds nothing ends it)
  // Per map: the deformed positions of the vertices that the last subdivision
  // for it measured, where on the sheet (reused by the map; empty: none).
  std::vector<std::vector<Vec3>> known;
  std::vector<std::vector<char>> known_on_sheet;
};

// Places `mesh` on every map's sheet and refines it for every map in turn,
// until a pass over all of them adds nothing (options.placement and
// options.subdivision). Errors as Deform's; kDeadlineExceeded past
// subdivision.time_budget_ms (all maps together).
Result<PreparedModel> PrepareModel(std::span<const SheetMap* const> maps, Mesh&& mesh,
                                   const DeformOptions& options);

// The deformation of a prepared model through `map`, the map `index` of
// those it was prepared for. The same for every caller that asks for the same
// frame: an animation's frame k and a single frame k are one computation.
// Its options are the preparation's (the subdivision is not read).
Result<DeformResult> DeformPrepared(const SheetMap& map, const PreparedModel& model, size_t index,
                                    const DeformOptions& options);

}  // namespace surfdeform
