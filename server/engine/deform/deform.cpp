// Just over ~600 lines: the single deformation (Deform) and the animation's
// (PrepareModel, DeformPrepared) share the placement, the map and the report
// that live here unexported.
#include "engine/deform/deform.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <span>

#include "engine/common/elapsed.hpp"
#include "engine/common/parallel.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/surface/surface_batch.hpp"

namespace surfdeform {
namespace {

using Mat3 = Eigen::Matrix3d;

// Options, mesh and sheet: kInvalidArgument for anything unusable.
Status ValidateInput(const FlatSheet& sheet, const Mesh& mesh, const PlacementOptions& o,
                     const SubdivisionOptions* subdivision) {
  SURFDEFORM_RETURN_IF_ERROR(ValidatePlacement(o));
  if (subdivision != nullptr) SURFDEFORM_RETURN_IF_ERROR(ValidateSubdivision(*subdivision));
  if (const std::string problem = CheckMesh(mesh); !problem.empty()) {
    return InvalidArgument("malformed mesh: " + problem, "mesh");
  }
  if (sheet.nu < 2 || sheet.nv < 2 ||
      sheet.flat.size() != static_cast<size_t>(sheet.nu) * sheet.nv) {
    return InvalidArgument("the flat sheet is empty or inconsistent", "surface");
  }
  if (const long long k = FirstNonFinite(mesh.positions); k >= 0) {
    return InvalidArgument("vertex position is not finite",
                           "mesh.positions[" + std::to_string(k) + "]");
  }
  return Status::Ok();
}

// What the map reads after the subdivision: the mesh to deform (the input or
// the refined one, in result->mesh), its placed coordinates (empty: placed
// on the fly), and the input vertices the subdivision deformed already. The
// spans view either the owned vectors or a PreparedModel's.
struct Refined {
  Refined() = default;
  // Moved, the vectors keep their buffers, so the spans stay valid; a copy's
  // spans would point into the original.
  Refined(Refined&&) = default;
  Refined& operator=(Refined&&) = default;
  Refined(const Refined&) = delete;
  Refined& operator=(const Refined&) = delete;

  const Mesh* source = nullptr;
  std::span<const Vec3> placed;
  std::span<const Vec3> known;  // per input vertex, where known_on_sheet
  std::span<const char> known_on_sheet;
  std::vector<Vec3> owned_placed, owned_known;
  std::vector<char> owned_on_sheet;
  bool located = false;  // the subdivision located the input vertices
  // Added to `placed` (an animation's frame: the first sheet's placed
  // coordinates moved onto this one's, PreparedModel::placed).
  Vec2 shift = Vec2::Zero();
  // Vertex k's placed coordinates: `placed`'s, else placed by `pl` now.
  Vec3 Placed(const Placement& pl, size_t k) const {
    if (placed.empty()) return pl.Apply(source->positions[k]);
    Vec3 abh = placed[k];
    abh.head<2>() += shift;
    return abh;
  }
  void Own() {
    placed = owned_placed;
    known = owned_known;
    known_on_sheet = owned_on_sheet;
  }
};

// The placed coordinates of every vertex of `mesh`.
std::vector<Vec3> PlaceAll(const Placement& pl, const Mesh& mesh, int threads_option) {
  const size_t n = mesh.positions.size();
  std::vector<Vec3> placed(n);
  const int threads = n >= 4096 ? ResolveThreads(threads_option) : 1;
  ParallelChunks(static_cast<int>(n), threads, [&](int, int begin, int end) {
    for (int k = begin; k < end; ++k) placed[k] = pl.Apply(mesh.positions[k]);
  });
  return placed;
}

// How far frame k's placed coordinates are from the first frame's: the
// placements differ only in their target.
Vec2 ShiftOf(const PreparedModel& model, size_t k) {
  return model.placements[k].target - model.placements.front().target;
}

void MoveBy(const Vec2& d, std::vector<Vec3>* placed) {
  if (d == Vec2::Zero()) return;
  for (Vec3& p : *placed) p.head<2>() += d;
}

// `placed` (on the first sheet) on map k's sheet: `placed` itself when the
// two coincide, else a moved copy in *storage.
const std::vector<Vec3>& PlacedOn(const PreparedModel& model, size_t k,
                                  const std::vector<Vec3>& placed, std::vector<Vec3>* storage) {
  const Vec2 d = ShiftOf(model, k);
  if (d == Vec2::Zero() || placed.empty()) return placed;
  *storage = placed;
  MoveBy(d, storage);
  return *storage;
}

// The subdivision, when asked for: refines `mesh` into result->mesh (or
// leaves it, when nothing is needed). Positions of the input vertices are
// asked for only when the map will not recompute them (no frame to carry).
Result<Refined> Refine(const SheetMap& map, const Placement& pl, const Mesh& mesh,
                       const PlacementOptions& o, const SubdivisionOptions* subdivision,
                       bool need_frame, const FootprintUse& footprint,
                       const SubdivisionStats* unrefined, DeformResult* result) {
  Refined r;
  r.source = &mesh;
  if (subdivision == nullptr || subdivision->mode == SubdivisionMode::kOff ||
      mesh.triangles.empty()) {
    return r;
  }
  if (unrefined != nullptr) {  // known to add nothing: mapped as without it
    result->stats.subdivision = *unrefined;
    result->stats.subdivision.time_ms = 0.0;
    result->unrefined = true;
    return r;
  }
  const auto ts = std::chrono::steady_clock::now();
  // Placed coordinates; footprints off the sheet are reported by the map
  // (subdivision continues the map past the border meanwhile).
  r.owned_placed = PlaceAll(pl, mesh, o.threads);
  SubdivisionOptions so = *subdivision;
  if (so.threads == 0) so.threads = o.threads;
  const InputPositions want = need_frame ? InputPositions::kNotWanted : InputPositions::kWanted;
  SURFDEFORM_ASSIGN_OR_RETURN(
      SubdivisionResult refined,
      Subdivide(mesh, r.owned_placed, map, o.outside, so, want, {}, footprint));
  r.located = true;
  result->stats.subdivision = refined.stats;
  if (refined.input_positions) {
    r.owned_known = std::move(*refined.input_positions);
    r.owned_on_sheet = std::move(refined.on_sheet);
  }
  if (refined.unchanged) {
    result->unrefined = true;
    if (&result->mesh != &mesh) result->mesh = Mesh{};  // as without subdivision
  } else {
    result->mesh = std::move(refined.mesh);
    r.owned_placed = std::move(refined.placed);
    r.source = &result->mesh;
  }
  r.Own();
  result->stats.subdivide_ms = MsSince(ts);
  return r;
}

// Sizes `out` for `in` and carries over what the map does not recompute,
// unless they are the same mesh (in place).
void PrepareOutput(const Mesh& in, Mesh* out, bool geometry_only = false) {
  if (out == &in) return;
  if (geometry_only) {
    out->positions.resize(in.positions.size());
    out->normals.resize(in.normals.size());
    out->tangents.resize(in.tangents.size());
    return;
  }
  out->triangles = in.triangles;
  out->groups = in.groups;
  out->uv0 = in.uv0;
  out->uv1 = in.uv1;
  out->colors = in.colors;
  out->positions.resize(in.positions.size());
  out->normals.resize(in.normals.size());
  out->tangents.resize(in.tangents.size());
}

// What the map found: input footprints off the sheet, and the first vertex
// whose deformation is not finite.
struct MapTally {
  size_t outside = 0;
  double worst = 0.0;
  long long bad = -1;
};

// A vertex's normal and tangent through the Jacobian `jac` of the map.
void CarryFrame(const Mesh& in, const Mat3& jac, const Mat3& linear, const Mat3& normal_linear,
                size_t k, Mesh* out) {
  const Mat3 total = jac * linear;
  if (!in.normals.empty()) {
    // J^-T n up to a positive factor (1 / det J), which the normalisation
    // removes: the cofactor matrix, i.e. cross products of J's columns.
    const Vec3 m = normal_linear * in.normals[k];
    const Vec3 nn = m.x() * jac.col(1).cross(jac.col(2)) + m.y() * jac.col(2).cross(jac.col(0)) +
                    m.z() * jac.col(0).cross(jac.col(1));
    out->normals[k] = nn.normalized();
  }
  if (!in.tangents.empty()) {
    const Vec4& t = in.tangents[k];
    const Vec3 tt = (total * t.head<3>()).normalized();
    const double w = total.determinant() < 0.0 ? -t.w() : t.w();
    out->tangents[k] = Vec4(tt.x(), tt.y(), tt.z(), w);
  }
}

// The deformation, vertex by vertex, of `r.source` into `out` (which may be
// the same mesh: each vertex reads only its own input before writing).
// Vertices are located one by one and evaluated in blocks
// (Surface::EvaluateMany, or Surface::OffsetMany without a frame to carry:
// four at a time on the bicubic Bezier patch).
MapTally MapVertices(const SheetMap& map, const Placement& pl, const Refined& r, size_t n_input,
                     const PlacementOptions& o, bool need_frame, const FootprintUse& footprint,
                     Mesh* out) {
  const Mesh& in = *r.source;
  const size_t n = in.positions.size();
  const Mat3 linear = pl.Linear();
  const Mat3 normal_linear = linear.inverse().transpose();
  const int threads = n >= 4096 ? ResolveThreads(o.threads) : 1;
  std::vector<MapTally> tally(threads);
  ParallelChunks(static_cast<int>(n), threads, [&](int chunk, int begin, int end) {
    MapTally& t = tally[chunk];
    auto note_bad = [&t](long long k) {
      if (t.bad < 0 || k < t.bad) t.bad = k;
    };
    SurfaceBatch batch(map.surface(), need_frame ? 2 : 1);
    SheetParameters params[SurfaceBatch::kSize];  // by slot, when carrying a frame
    auto finish = [&](int slot, int k, const SurfacePoint& s, double h) {  // with a frame
      Vec3 nrm;
      const Mat3 jac = DeformJacobian(s, params[slot], h, &nrm);  // d(position)/d(a, b, h)
      out->positions[k] = s.p + h * nrm;
      CarryFrame(in, jac, linear, normal_linear, k, out);
      const bool finite = out->positions[k].allFinite() &&
                          (in.normals.empty() || out->normals[k].allFinite()) &&
                          (in.tangents.empty() || out->tangents[k].allFinite());
      if (!finite) note_bad(k);
    };
    auto place = [&](int k, const Vec3& moved) {  // no frame: the position only
      out->positions[k] = moved;
      if (!moved.allFinite()) note_bad(k);
    };
    auto drain = [&] { need_frame ? batch.Drain(finish) : batch.DrainOffsets(place); };
    int hint = -1;  // the previous vertex's cell
    for (int k = begin; k < end; ++k) {
      if (static_cast<size_t>(k) < r.known.size() && r.known_on_sheet[k]) {
        out->positions[k] = r.known[k];  // on the sheet, deformed by the subdivision already
        if (!r.known[k].allFinite()) note_bad(k);
        continue;
      }
      const Vec3 abh = r.Placed(pl, k);
      // Vertices added by the subdivision inside faces whose corners are on
      // the sheet continue its map past a concave border.
      const bool added = static_cast<size_t>(k) >= n_input;
      const OutsideMode mode =
          added && o.outside == OutsideMode::kError ? OutsideMode::kExtrapolate : o.outside;
      const SheetParameters p =
          added ? map.Parameters(abh.head<2>(), mode, need_frame, &hint)
                : footprint.Parameters(map, k, abh.head<2>(), mode, need_frame, &hint);
      if (p.outside && !added) {
        ++t.outside;
        t.worst = std::max(t.worst, p.outside_distance);
      }
      if (p.outside && mode == OutsideMode::kError) continue;
      const int slot = batch.Add(k, p.uv, abh.z());
      if (need_frame) params[slot] = p;
      if (batch.full()) drain();
    }
    drain();
  });
  MapTally total;
  for (const MapTally& t : tally) {
    total.outside += t.outside;
    total.worst = std::max(total.worst, t.worst);
    if (total.bad < 0) total.bad = t.bad;
  }
  return total;
}

// Mesh::distortion of every vertex of `out`, the deformation of `r.source`:
// the singular values of d(position)/d(a, b) at its placed coordinates,
// minus 1 (an extra pass: only when asked for).
void MapDistortion(const SheetMap& map, const Placement& pl, const Refined& r,
                   const PlacementOptions& o, Mesh* out) {
  const Mesh& in = *r.source;
  const size_t n = in.positions.size();
  out->distortion.resize(n);
  const int threads = n >= 4096 ? ResolveThreads(o.threads) : 1;
  // Outside the sheet the map is continued as the vertices were (clamped or
  // extrapolated); with kError none is outside by now.
  const OutsideMode mode = o.outside == OutsideMode::kError ? OutsideMode::kExtrapolate : o.outside;
  ParallelChunks(static_cast<int>(n), threads, [&](int, int begin, int end) {
    int hint = -1;
    for (int k = begin; k < end; ++k) {
      const Vec3 abh = r.Placed(pl, k);
      const SheetParameters p = map.Parameters(abh.head<2>(), mode, true, &hint);
      const SurfacePoint s = map.surface().Evaluate(p.uv.x(), p.uv.y(), 2);
      Vec3 nrm;
      const Mat3 jac = DeformJacobian(s, p, abh.z(), &nrm);
      out->distortion[k] = SingularValues(jac.leftCols<2>()) - Vec2::Ones();
    }
  });
}

// The statistics, and the errors the map found.
Status Report(const MapTally& t, const Mesh& in, size_t n_input, const Placement& pl,
              const PlacementOptions& o, DeformStats* st) {
  st->vertices = in.positions.size();
  st->triangles = in.triangles.size();
  if (st->subdivision.mode == SubdivisionMode::kOff) {
    st->subdivision.vertices_before = st->subdivision.vertices_after = st->vertices;
    st->subdivision.triangles_before = st->subdivision.triangles_after = st->triangles;
  }
  st->scale = pl.scale;
  st->up = pl.up;
  st->up_reason = pl.up_reason;
  st->outside = t.outside;
  st->max_outside_distance = t.worst;
  if (st->outside > 0 && o.outside == OutsideMode::kError) {
    return OutsideSheetError(st->outside, n_input, st->max_outside_distance);
  }
  if (t.bad >= 0) {
    return Degenerate("the deformation of vertex " + std::to_string(t.bad) +
                          " is not finite (the surface normal vanishes there)",
                      "surface");
  }
  return Status::Ok();
}

// The deformation of `mesh` with its parts moved as rigid bodies (no
// subdivision); the distortion of a rigid motion is 0.
Status DeformRigidly(const SheetMap& map, const Placement& pl, const Mesh& mesh,
                     const DeformOptions& options, DeformResult* result) {
  const PlacementOptions& o = options.placement;
  PrepareOutput(mesh, &result->mesh, options.geometry_only);
  int parts = 0;
  const std::vector<int> part = RigidParts(mesh, o.rigid, &parts);
  RigidStats rigid = PlaceRigidParts(map, pl, mesh, part, parts, o.outside, &result->mesh);
  rigid.mode = o.rigid;
  MapTally t;
  for (size_t k = 0; k < mesh.positions.size(); ++k) {
    if (rigid.each[part[k]].outside) ++t.outside;
    if (!result->mesh.positions[k].allFinite() && t.bad < 0) t.bad = static_cast<long long>(k);
  }
  t.worst = rigid.max_outside_distance;
  result->stats.rigid = std::move(rigid);
  SURFDEFORM_RETURN_IF_ERROR(Report(t, result->mesh, mesh.positions.size(), pl, o, &result->stats));
  if (options.distortion) {
    result->mesh.distortion.assign(mesh.positions.size(), Vec2::Zero());
    result->stats.distortion = SummarizeDistortion(result->mesh);
  }
  return Status::Ok();
}

// The deformation of `mesh`, in place in result->mesh (which holds it),
// with what `memo` recalls (a plain DeformMemo recalls nothing).
Status DeformInPlace(const SheetMap& map, const DeformOptions& options, DeformMemo& memo,
                     DeformResult* result) {
  const auto t0 = std::chrono::steady_clock::now();
  const Mesh& mesh = result->mesh;
  const PlacementOptions& o = options.placement;
  const SubdivisionOptions* subdivision =
      options.subdivision.mode == SubdivisionMode::kOff ? nullptr : &options.subdivision;
  SURFDEFORM_RETURN_IF_ERROR(ValidateInput(map.sheet(), mesh, o, subdivision));
  std::optional<Placement> recalled = memo.RecallPlacement();
  if (recalled) {
    result->placement = *recalled;
  } else {
    SURFDEFORM_ASSIGN_OR_RETURN(result->placement, ComputePlacement(map, mesh.positions, o));
  }
  const Placement& pl = result->placement;
  result->stats.turns = TurnsRound(map, pl, mesh.positions);
  // The subdivision keeps which attributes there are, so this holds for the
  // refined mesh too.
  const bool need_frame = !mesh.normals.empty() || !mesh.tangents.empty();
  const size_t n_input = mesh.positions.size();
  if (o.rigid != RigidMode::kNone) return DeformRigidly(map, pl, mesh, options, result);
  // The footprint: recalled, or recorded by whichever pass locates first (the
  // map then reads what the subdivision recorded).
  const std::shared_ptr<const SheetFootprint> known = memo.RecallFootprint();
  FootprintUse footprint;
  if (known != nullptr && known->location.size() == n_input) {
    footprint.known = known.get();
  } else if (memo.WantsFootprint() && map.cell_wise()) {
    SheetLocation unlocated;
    unlocated.i = -1;
    result->footprint.location.assign(n_input, unlocated);
    footprint.record = &result->footprint;
  }
  const std::optional<SubdivisionStats> unrefined =
      subdivision != nullptr ? memo.RecallUnrefined() : std::nullopt;
  SURFDEFORM_ASSIGN_OR_RETURN(const Refined r,
                              Refine(map, pl, mesh, o, subdivision, need_frame, footprint,
                                     unrefined ? &*unrefined : nullptr, result));
  if (r.located && footprint.record != nullptr) footprint = {footprint.record, nullptr};
  PrepareOutput(*r.source, &result->mesh);
  // Before the map, which may overwrite the source's positions (in place).
  if (options.distortion) MapDistortion(map, pl, r, o, &result->mesh);
  const MapTally t = MapVertices(map, pl, r, n_input, o, need_frame, footprint, &result->mesh);
  SURFDEFORM_RETURN_IF_ERROR(Report(t, *r.source, n_input, pl, o, &result->stats));
  if (options.distortion) result->stats.distortion = SummarizeDistortion(result->mesh);
  result->stats.time_ms = MsSince(t0);
  return Status::Ok();
}

}  // namespace

Result<DeformResult> Deform(const SheetMap& map, Mesh mesh, const DeformOptions& options,
                            DeformMemo* memo) {
  DeformResult result;
  result.mesh = std::move(mesh);
  DeformMemo nothing;  // recalls nothing, learns nothing
  DeformMemo& use = memo != nullptr ? *memo : nothing;
  SURFDEFORM_RETURN_IF_ERROR(DeformInPlace(map, options, use, &result));
  use.Learn(result);
  return result;
}

Result<PreparedModel> PrepareModel(std::span<const SheetMap* const> maps, Mesh&& mesh,
                                   const DeformOptions& options) {
  const PlacementOptions& o = options.placement;
  const SubdivisionOptions& subdivision = options.subdivision;
  if (maps.empty()) return InvalidArgument("no sheet to place the model on", "surface");
  const SheetMap& first = *maps.front();
  SURFDEFORM_RETURN_IF_ERROR(ValidateInput(first.sheet(), mesh, o, &subdivision));
  for (const SheetMap* m : maps) {
    if (m->sheet().nu != first.sheet().nu || m->sheet().nv != first.sheet().nv) {
      return InvalidArgument("the sheets of one model must share their grid", "surface");
    }
  }
  PreparedModel model;
  SURFDEFORM_ASSIGN_OR_RETURN(FramePlacements placements,
                              ComputeFramePlacements(maps, mesh.positions, o));
  model.placements = std::move(placements.each);
  model.fit_frame = placements.fit_frame;
  model.input_vertices = mesh.positions.size();
  model.need_frame = !mesh.normals.empty() || !mesh.tangents.empty();
  model.known.resize(maps.size());
  model.known_on_sheet.resize(maps.size());
  model.mesh = std::move(mesh);
  SubdivisionStats& st = model.subdivision;
  st.vertices_before = st.vertices_after = model.mesh.positions.size();
  st.triangles_before = st.triangles_after = model.mesh.triangles.size();
  if (o.rigid != RigidMode::kNone || subdivision.mode == SubdivisionMode::kOff ||
      model.mesh.triangles.empty()) {
    return model;
  }
  const auto ts = std::chrono::steady_clock::now();
  st.mode = subdivision.mode;
  model.placed = PlaceAll(model.placements.front(), model.mesh, o.threads);
  SubdivisionOptions so = subdivision;
  if (so.threads == 0) so.threads = o.threads;
  const InputPositions want =
      model.need_frame ? InputPositions::kNotWanted : InputPositions::kWanted;
  // Each pass first measures every map on the current mesh, the maps spread
  // over the threads (one each: a frame's subdivision alone is too small to
  // share well). If none adds a vertex, every frame meets the tolerance on
  // this one topology, and the pass's measurements are the statistics. Else
  // the maps are refined in turn from the first that added any, each on the
  // mesh the previous one left (a refinement only adds vertices, after the
  // ones it was given, in order, so what one frame needed stays for the
  // others), and the next pass measures them all again.
  constexpr int kMaxPasses = 4;
  auto budget_left = [&](SubdivisionOptions* left) -> Status {
    if (subdivision.time_budget_ms <= 0.0) return Status::Ok();
    left->time_budget_ms = subdivision.time_budget_ms - MsSince(ts);
    if (left->time_budget_ms > 0.0) return Status::Ok();
    return Status::DeadlineExceeded(
        "the subdivision for every frame ran past its time budget of " +
            std::to_string(static_cast<long long>(subdivision.time_budget_ms)) + " ms",
        "subdivision", subdivision.time_budget_ms, MsSince(ts));
  };
  auto grows = [&model](const SubdivisionResult& r) {
    return !r.unchanged && r.mesh.positions.size() > model.mesh.positions.size();
  };
  auto keep_positions = [&model](size_t k, SubdivisionResult* r) {
    if (r->input_positions) {
      model.known[k] = std::move(*r->input_positions);
      model.known_on_sheet[k] = std::move(r->on_sheet);
    } else {
      model.known[k].clear();
      model.known_on_sheet[k].clear();
    }
  };
  const int n_maps = static_cast<int>(maps.size());
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    SURFDEFORM_RETURN_IF_ERROR(budget_left(&so));
    SubdivisionOptions one = so;
    const int threads = std::min(n_maps, ResolveThreads(so.threads));
    one.threads = threads > 1 ? 1 : so.threads;
    // The faces' extents on the sheet are those of the placed model, the same
    // for every map: measured once per pass.
    const std::vector<FaceExtent> extents = FaceExtents(model.mesh, model.placed);
    std::vector<Result<SubdivisionResult>> results(maps.size(), NotComputed());
    // A measurement keeps only what the pass goes on to use: the refined
    // mesh of the first frame that grows (the one the refinement starts
    // from), and the input vertices' positions of the frames before it. The
    // rest shrinks to its statistics as soon as it is made, so a pass holds
    // a mesh per thread at most, not one per frame (300 frames of a refined
    // label held 6.7 GB).
    std::vector<char> grew(maps.size(), 0);
    std::atomic<int> lowest_growth{n_maps};
    ParallelChunks(n_maps, threads, [&](int, int begin, int end) {
      std::vector<Vec3> moved;
      for (int k = begin; k < end; ++k) {
        results[k] = Subdivide(model.mesh, PlacedOn(model, k, model.placed, &moved), *maps[k],
                               o.outside, one, want, extents);
        if (!results[k].ok()) continue;
        SubdivisionResult& r = *results[k];
        int lowest = lowest_growth.load();
        if (grows(r)) {
          grew[k] = 1;
          while (k < lowest && !lowest_growth.compare_exchange_weak(lowest, k)) {
          }
          if (k < lowest) continue;  // the first to grow so far: kept whole
        }
        r.mesh = Mesh{};
        r.placed = std::vector<Vec3>{};
        if (k > lowest) {  // past a frame that grows: refined again, never kept
          r.input_positions.reset();
          r.on_sheet = std::vector<char>{};
        }
      }
    });
    int first_growth = -1;
    st.max_deviation = st.max_estimated_deviation = 0.0;
    st.measured_points = 0;
    for (int k = 0; k < n_maps; ++k) {
      if (!results[k].ok()) return results[k].status();
      const SubdivisionStats& rs = results[k]->stats;
      st.max_deviation = std::max(st.max_deviation, rs.max_deviation);
      st.max_estimated_deviation = std::max(st.max_estimated_deviation, rs.max_estimated_deviation);
      st.measured_points += rs.measured_points;
      st.epsilon = rs.epsilon;
      st.tolerance = rs.tolerance;
      if (first_growth < 0 && grew[k]) first_growth = k;
      // A frame that adds no vertex may still re-triangulate faces it
      // measured; that is kept only if another frame adds points anyway.
      if (first_growth < 0 || k < first_growth) keep_positions(k, &*results[k]);
    }
    ++model.subdivision_passes;
    if (first_growth < 0) break;
    for (int k = first_growth; k < n_maps; ++k) {
      Result<SubdivisionResult> refined = std::move(results[k]);
      if (k > first_growth) {
        SURFDEFORM_RETURN_IF_ERROR(budget_left(&so));
        std::vector<Vec3> moved;
        refined = Subdivide(model.mesh, PlacedOn(model, k, model.placed, &moved), *maps[k],
                            o.outside, so, want);
        if (!refined.ok()) return refined.status();
      }
      st.edge_points_considered += refined->stats.edge_points_considered;
      st.edge_points_kept += refined->stats.edge_points_kept;
      st.face_points_considered += refined->stats.face_points_considered;
      st.face_points_kept += refined->stats.face_points_kept;
      st.refinement_points += refined->stats.refinement_points;
      keep_positions(k, &*refined);
      if (grows(*refined)) {
        model.mesh = std::move(refined->mesh);
        model.placed = std::move(refined->placed);
        MoveBy(-ShiftOf(model, k), &model.placed);  // back onto the first sheet
      }
    }
  }
  st.vertices_after = model.mesh.positions.size();
  st.triangles_after = model.mesh.triangles.size();
  model.subdivide_ms = MsSince(ts);
  st.time_ms = model.subdivide_ms;
  return model;
}

Result<DeformResult> DeformPrepared(const SheetMap& map, const PreparedModel& model, size_t index,
                                    const DeformOptions& options) {
  const PlacementOptions& o = options.placement;
  const auto t0 = std::chrono::steady_clock::now();
  DeformResult result;
  if (index >= model.placements.size()) {
    return InvalidArgument("no placement for map " + std::to_string(index), "surface");
  }
  const Placement& pl = model.placements[index];
  if (o.rigid != RigidMode::kNone) {
    SURFDEFORM_RETURN_IF_ERROR(DeformRigidly(map, pl, model.mesh, options, &result));
    result.stats.fit_frame = model.fit_frame;
    result.stats.time_ms = MsSince(t0);
    return result;
  }
  Refined r;
  r.source = &model.mesh;
  r.placed = model.placed;
  r.shift = ShiftOf(model, index);
  if (index < model.known.size()) {
    r.known = model.known[index];
    r.known_on_sheet = model.known_on_sheet[index];
  }
  PrepareOutput(model.mesh, &result.mesh, options.geometry_only);
  if (options.distortion) MapDistortion(map, pl, r, o, &result.mesh);
  const MapTally t =
      MapVertices(map, pl, r, model.input_vertices, o, model.need_frame, {}, &result.mesh);
  result.stats.subdivision = model.subdivision;
  result.stats.subdivide_ms = model.subdivide_ms;
  result.stats.fit_frame = model.fit_frame;
  if (index == 0) {  // the first frame's stats stand for the animation's
    result.stats.turns = TurnsRound(
        map, pl, std::span<const Vec3>(model.mesh.positions).first(model.input_vertices));
  }
  SURFDEFORM_RETURN_IF_ERROR(Report(t, model.mesh, model.input_vertices, pl, o, &result.stats));
  if (options.distortion) result.stats.distortion = SummarizeDistortion(result.mesh);
  result.stats.time_ms = MsSince(t0);
  return result;
}

}  // namespace surfdeform
