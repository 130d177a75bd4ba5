#include "service/service.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <thread>

#include "base/fault_points.hpp"
#include "engine/animation.hpp"
#include "engine/deform.hpp"
#include "engine/elapsed.hpp"
#include "engine/flatten.hpp"
#include "engine/parallel.hpp"
#include "engine/sheet_marks.hpp"
#include "engine/surface_spec.hpp"
#include "meshio/animation_glb.hpp"
#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"
#include "proto/api.hpp"
#include "proto/content_hash.hpp"
#include "proto/json_object.hpp"
#include "proto/map_api.hpp"
#include "service/admission.hpp"
#include "service/flat_sheet_svg.hpp"
#include "service/memory_budget.hpp"
#include "service/output_negotiation.hpp"
#include "service/placement_memo.hpp"
#include "service/sheet_codec.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// A flattened surface as the cache holds it: immutable once built.
struct CachedSurface {
  std::string id;
  proto::SurfaceRequest request;
  std::unique_ptr<const Surface> surface;
  FlatSheet sheet;
  double flatten_ms = 0.0;
  size_t bytes = 0;
};

// An animation's sheets as the cache holds them: immutable once built.
struct CachedAnimation {
  std::string id;
  proto::AnimationRequest request;
  AnimatedSheets sheets;
  double flatten_ms = 0.0;
  size_t bytes = 0;
};

size_t EstimateBytes(const CachedAnimation& a) {
  size_t samples = 0;
  for (const FlatSheet& s : a.sheets.sheets) samples += s.points.size();
  // Samples: position, normal, flat position; each frame's surface about as
  // much as a key's spec (a Bezier's control points, a grid's points).
  return sizeof(CachedAnimation) + samples * (24 + 24 + 16) + a.sheets.surfaces.size() * 4096 +
         1024;
}

size_t EstimateBytes(const CachedSurface& s) {
  const size_t samples = s.sheet.points.size();
  size_t spec = 0;
  std::visit(
      [&spec](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, BezierSpec>) spec = v.control_points.size() * 24;
        if constexpr (std::is_same_v<T, BSplineSpec>) {
          spec = v.control_points.size() * 32 + (v.knots_u.size() + v.knots_v.size()) * 8;
        }
        if constexpr (std::is_same_v<T, GridSpec>) spec = v.points.size() * 24 * 4;
      },
      s.request.surface);
  // Samples: position, normal and flat position; the surface keeps about as
  // much again as its spec (copies, derived coefficients).
  return sizeof(CachedSurface) + samples * (24 + 24 + 16) + 2 * spec + 1024;
}

json SheetSummary(const CachedSurface& s, bool cached) {
  return {{"id", s.id},
          {"cached", cached},
          {"grid", {{"nu", s.sheet.nu}, {"nv", s.sheet.nv}}},
          {"method", s.sheet.method},
          {"quality", proto::QualityJson(s.sheet.quality)},
          {"timing_ms", {{"flatten", s.flatten_ms}}}};
}

// A request's time budget: what is left of it, and the error once it is spent.
class RequestClock {
 public:
  explicit RequestClock(double budget_ms) : start_(Clock::now()), budget_ms_(budget_ms) {}
  double remaining_ms() const { return budget_ms_ - MsSince(start_); }
  // kDeadlineExceeded when the budget is spent, naming the phase it ran out in.
  Status Check(const char* phase) const {
    const double spent = MsSince(start_);
    if (spent <= budget_ms_) return Status::Ok();
    return Status::DeadlineExceeded(
        "this server's time budget of " + std::to_string(static_cast<long long>(budget_ms_)) +
            " ms per request ran out in the request's " + phase + " (" +
            std::to_string(static_cast<long long>(spent)) +
            " ms spent); send a smaller mesh or grid, or ask for a looser subdivision",
        "request", budget_ms_, spent);
  }
  // A budget for the next phase: what is left, at most `cap` (> 0).
  double BudgetFor(double cap) const { return std::max(1.0, std::min(cap, remaining_ms())); }

 private:
  Clock::time_point start_;
  double budget_ms_;
};

// A phase's error; but a phase stopped by its own time budget once the
// request's budget is spent too reports the request's budget.
Status WithinBudget(const RequestClock& clock, const char* phase, Status error) {
  const bool timed_out = error.code() == ErrorCode::kDeadlineExceeded;
  Status late = clock.Check(phase);
  return timed_out && !late.ok() ? late : error;
}

// What an import may read, from the service's limits (glTF's JSON nests
// deeper than a request's).
ImportLimits ImportLimitsOf(const ServiceLimits& limits) {
  ImportLimits l;
  l.max_bytes = limits.max_body_bytes;
  l.max_vertices = limits.max_vertices;
  l.max_triangles = limits.max_triangles;
  l.max_json_depth = 2 * limits.max_json_depth;
  l.max_image_bytes = limits.max_body_bytes;  // they travel to the output as they came
  return l;
}

// The X-Surfdeform-Stats of a deformation.
json DeformStatsHeader(const std::string& id, const FlattenQuality& quality, bool hit,
                       proto::OutputFormat format, const ImportedMesh& imported,
                       const DeformStats& st, bool placement_reused = false,
                       bool subdivision_reused = false) {
  json j = {{"surface_id", id},
            {"cached", hit},
            {"format", proto::OutputFormatName(format)},
            {"input_format", MeshFormatName(imported.format)},
            {"vertices", st.vertices},
            {"triangles", st.triangles},
            {"subdivision", proto::SubdivisionStatsJson(st.subdivision)},
            {"placement", proto::DeformStatsJson(st)},
            {"quality", proto::QualityJson(quality)},
            {"warnings", imported.warnings}};
  j["placement"]["reused"] = placement_reused;  // from the memo: the same model came before
  // Not run: it added nothing to the same model with the same options before.
  j["subdivision"]["reused"] = subdivision_reused;
  if (st.rigid.mode != RigidMode::kNone) {
    json each = json::array();
    for (size_t k = 0; k < st.rigid.each.size() && k < 1000; ++k) {
      const RigidPartStats& e = st.rigid.each[k];
      each.push_back({{"vertices", e.vertices}, {"lift", e.lift}, {"sink", e.sink}});
    }
    j["rigid"] = {{"mode", NameOf<RigidMode>(kRigidModes, st.rigid.mode)},
                  {"parts", st.rigid.parts},
                  {"max_lift", st.rigid.max_lift},
                  {"max_sink", st.rigid.max_sink},
                  {"each", std::move(each)}};  // the first 1000 parts (StatsHeader cuts more)
  }
  if (st.distortion.computed) {
    j["distortion"] = {
        {"max", st.distortion.max}, {"p95", st.distortion.p95}, {"mean", st.distortion.mean}};
  }
  return j;
}

// output.distortion travels only in formats that name custom attributes.
Status CheckDistortionFormat(const proto::OutputOptions& o, proto::OutputFormat format) {
  using F = proto::OutputFormat;
  if (!o.distortion || format == F::kGlb || format == F::kGlbPlain || format == F::kPly) {
    return Status::Ok();
  }
  return InvalidArgument(std::string("the distortion map is written in glb, glb_plain or ply "
                                     "output (a _DISTORTION attribute, or two PLY properties); "
                                     "the output format is ") +
                             proto::OutputFormatName(format),
                         "output.distortion");
}

// POST /v1/surfaces/{id}/map: the input counts (published at /v1/info) and
// the points resampled polylines may have in all.
constexpr proto::MapLimits kMapLimits;
constexpr size_t kMaxMapOutputPoints = 1'000'000;
// Placements the memo keeps (~250 bytes each with their index).
constexpr size_t kPlacementMemoEntries = 1024;

std::string Dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

// The JSON path of the first number in `j` that is not finite ("" if none):
// nlohmann writes such a number as null, which a client would read as
// "absent" or choke on.
std::string FirstNonFiniteNumber(const json& j, const std::string& path) {
  if (j.is_number_float()) return std::isfinite(j.get<double>()) ? "" : path;
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      std::string found = FirstNonFiniteNumber(value, path.empty() ? key : path + "." + key);
      if (!found.empty()) return found;
    }
  } else if (j.is_array()) {
    for (size_t k = 0; k < j.size(); ++k) {
      std::string found = FirstNonFiniteNumber(j[k], path + "[" + std::to_string(k) + "]");
      if (!found.empty()) return found;
    }
  }
  return "";
}

// A reply's JSON (a body or the stats header), refused where a number in it
// is not finite: every number the service writes is finite.
Result<std::string> DumpFinite(const json& j, const char* what) {
  const std::string at = FirstNonFiniteNumber(j, "");
  if (at.empty()) return Dump(j);
  return Status(ErrorCode::kInvalidArgument,
                std::string("the ") + what + "'s " + at +
                    " would not be a finite number: the request's coordinates or sizes are "
                    "too large to compute with in double precision",
                at);
}

// The X-Surfdeform-Stats header's JSON. Header lines have limits on the
// way: cpp-httplib's clients (the CLI) read at most 8 KB a line, and nginx
// fails a response whose headers outgrow proxy_buffer_size (4 KB by
// default) with 502. The per-item lists ("each": a rigid model's parts, an
// animation's frames) are cut to their first items until the text fits
// kMaxStatsHeaderBytes; "each_omitted" beside a list counts what was cut.
constexpr size_t kMaxStatsHeaderBytes = 2048;

// The objects under `j` that hold an "each" list; not those inside such a
// list, whose items the cut erases (a pointer to one would dangle).
void CollectLists(json& j, std::vector<json*>* lists) {
  if (j.is_object()) {
    for (auto& [key, value] : j.items()) {
      if (key == "each" && value.is_array()) {
        lists->push_back(&j);
      } else {
        CollectLists(value, lists);
      }
    }
  } else if (j.is_array()) {
    for (json& item : j) CollectLists(item, lists);
  }
}

Result<std::string> StatsHeader(json stats) {
  SURFDEFORM_ASSIGN_OR_RETURN(std::string text, DumpFinite(stats, "statistics"));
  std::vector<json*> owners;  // objects that hold an "each" list
  CollectLists(stats, &owners);
  while (text.size() > kMaxStatsHeaderBytes) {
    json* longest = nullptr;
    for (json* o : owners) {
      if (longest == nullptr || (*o)["each"].size() > (*longest)["each"].size()) longest = o;
    }
    if (longest == nullptr || (*longest)["each"].empty()) break;
    json& each = (*longest)["each"];
    const size_t cut = (each.size() + 1) / 2;
    each.erase(each.end() - static_cast<long>(cut), each.end());
    (*longest)["each_omitted"] = longest->value("each_omitted", size_t{0}) + cut;
    text = Dump(stats);
  }
  return text;
}

// A deformed mesh encoded as asked, and the reply around it: `timings` gain
// the encoding's.
Result<Reply> MeshReply(const Mesh& mesh, const proto::OutputOptions& output,
                        proto::OutputFormat format, const ImportedMesh& imported, bool hit,
                        std::vector<Timing> timings, const json& stats) {
  const auto t0 = Clock::now();
  ExportOptions export_options;
  export_options.draco = output.draco;
  export_options.glb_draco = format == proto::OutputFormat::kGlb;
  export_options.materials = imported.materials;
  export_options.look = imported.look;
  SURFDEFORM_ASSIGN_OR_RETURN(auto bytes,
                              ExportMesh(mesh, proto::OutputMeshFormat(format), export_options));
  timings.push_back({"encode", MsSince(t0)});
  Reply reply;
  reply.cache_hit = hit;
  reply.body = std::move(bytes);
  reply.content_type = proto::OutputMediaType(format);
  reply.timings = std::move(timings);
  SURFDEFORM_ASSIGN_OR_RETURN(reply.stats_json, StatsHeader(stats));
  reply.etag = proto::Sha256Hex(reply.body, 32);
  return reply;
}

}  // namespace

struct Service::Impl {
  explicit Impl(ServiceOptions o)
      : options(Normalised(o)),
        shared(options.shared_tier),
        cache(options.limits.cache_bytes, [](const CachedSurface& s) { return s.bytes; }),
        animations(options.limits.cache_bytes, [](const CachedAnimation& a) { return a.bytes; }),
        admission(AdmissionOptions{options.limits.max_in_flight, options.limits.max_queued,
                                   options.limits.queue_timeout_ms, Cores()}) {}

  static int Cores() { return ResolveThreads(0); }  // one per core

  static ServiceOptions Normalised(ServiceOptions o) {
    if (o.limits.max_in_flight <= 0) o.limits.max_in_flight = Cores();
    if (o.limits.max_queued < 0) o.limits.max_queued = 4 * Cores();
    return o;
  }

  // Threads for a request's own parallel work: what its ticket allows (all
  // cores alone, one under load), at most --engine-threads when that is set.
  int ThreadsFor(const Admission::Ticket& ticket) const {
    const int t = ticket.threads();
    return options.engine_threads > 0 ? std::min(options.engine_threads, t) : t;
  }

  Status CheckGrid(const SamplingOptions& s) const {
    const int side = std::max(s.nu, s.nv);
    if (side > options.limits.max_grid_side) {
      return Status::LimitExceeded(
          "the sampling grid is " + std::to_string(s.nu) + " x " + std::to_string(s.nv) +
              "; this server flattens at most " + std::to_string(options.limits.max_grid_side) +
              " samples per side",
          s.nu >= s.nv ? "sampling.nu" : "sampling.nv", options.limits.max_grid_side, side);
    }
    return CheckMemory(
        kSheetBytesPerSample * s.nu * s.nv, options.limits.request_memory_bytes,
        "flattening a " + std::to_string(s.nu) + " x " + std::to_string(s.nv) + " grid",
        "sampling");
  }

  // The flattened surface for `request`, from the cache or flattened now. With
  // `admit`, only the flattening itself takes a work-in-flight ticket: a cache
  // hit, or a wait on another request's flattening of the same surface, is
  // never refused by the limit (checklist 27; the wait is bounded by that
  // flattening's own time budget).
  Result<std::shared_ptr<const CachedSurface>> Flattened(const proto::SurfaceRequest& request,
                                                         const RequestClock& clock, bool* hit,
                                                         bool admit = false) {
    SURFDEFORM_RETURN_IF_ERROR(CheckGrid(request.sampling));
    const std::string id = proto::SurfaceId(request);
    bool from_shared = false;  // computed here, but read from the second level
    auto result = cache.GetOrCompute(
        id,
        [&]() -> Result<std::shared_ptr<const CachedSurface>> {
          // The second level first; then, holding its lock (or when another
          // replica holds it but never finishes), flatten here.
          std::optional<SharedLock> lock;
          if (shared != nullptr) {
            if (auto e = FromShared(id)) {
              from_shared = true;
              return e;
            }
            std::string token;
            switch (shared->TryLock(SheetLockKey(id), &token)) {
              case SharedTier::Lock::kAcquired:
                lock.emplace(shared.get(), SheetLockKey(id), std::move(token));
                break;
              case SharedTier::Lock::kHeldElsewhere:
                if (auto e = WaitForShared(id, clock)) {
                  from_shared = true;
                  return e;
                }
                break;
              case SharedTier::Lock::kUnavailable:
                break;
            }
          }
          std::optional<Admission::Ticket> ticket;
          if (admit) {
            SURFDEFORM_ASSIGN_OR_RETURN(auto t, admission.Enter(clock.remaining_ms()));
            ticket.emplace(std::move(t));
          }
          const auto t0 = Clock::now();
          auto surface = MakeSurface(request.surface);
          if (!surface.ok()) return surface.status().WithFieldPrefix("surface");
          FlattenOptions flatten = request.flatten;
          flatten.threads = ticket ? ThreadsFor(*ticket) : options.engine_threads;
          flatten.time_budget_ms = clock.BudgetFor(options.limits.flatten_time_budget_ms);
          auto sheet = FlattenSurface(**surface, request.sampling, flatten);
          if (!sheet.ok()) {
            const Status& s = sheet.status();
            // Sampling errors name a sample of the surface.
            return s.field().empty() ? Status(s.code(), s.message(), "surface") : s;
          }
          auto entry = std::make_shared<CachedSurface>();
          entry->id = id;
          entry->request = request;
          entry->surface = std::move(*surface);
          entry->sheet = std::move(*sheet);
          entry->flatten_ms = MsSince(t0);
          entry->bytes = EstimateBytes(*entry);
          if (shared != nullptr) {
            shared->Put(SheetKey(id),
                        EncodeSheet(entry->sheet,
                                    {proto::CanonicalJson(request).dump(), entry->flatten_ms}));
          }
          return std::shared_ptr<const CachedSurface>(std::move(entry));
        },
        hit);
    if (from_shared) *hit = true;
    return result;
  }

  // Releases a cross-replica flattening lock however the flattening ends.
  class SharedLock {
   public:
    SharedLock(SharedTier* tier, std::string key, std::string token)
        : tier_(tier), key_(std::move(key)), token_(std::move(token)) {}
    SharedLock(const SharedLock&) = delete;
    ~SharedLock() { tier_->Unlock(key_, token_); }

   private:
    SharedTier* tier_;
    std::string key_, token_;
  };

  // Surface `id` from the second level, checked and rebuilt; nullptr for a
  // miss, an unreachable tier, or a value that fails any check (counted).
  std::shared_ptr<const CachedSurface> FromShared(const std::string& id) {
    std::string value;
    if (shared->Get(SheetKey(id), &value) != SharedTier::Lookup::kHit) return nullptr;
    auto entry = Rebuild(id, value);
    if (!entry.ok()) {
      shared->CountCorrupt();
      return nullptr;
    }
    return *entry;
  }

  Result<std::shared_ptr<const CachedSurface>> Rebuild(const std::string& id,
                                                       std::string_view value) {
    SURFDEFORM_ASSIGN_OR_RETURN(auto decoded, DecodeSheet(value, options.limits.max_grid_side));
    SURFDEFORM_ASSIGN_OR_RETURN(
        auto parsed, proto::ParseRequestJson(decoded.parts.canonical_request,
                                             options.limits.max_json_depth, "shared_tier"));
    SURFDEFORM_ASSIGN_OR_RETURN(auto request, proto::ParseSurfaceRequest(parsed));
    if (proto::SurfaceId(request) != id || request.sampling.nu != decoded.sheet.nu ||
        request.sampling.nv != decoded.sheet.nv) {
      return Status(ErrorCode::kMalformed, "the shared sheet answers another request",
                    "shared_tier");
    }
    SURFDEFORM_RETURN_IF_ERROR(CheckGrid(request.sampling));
    SURFDEFORM_ASSIGN_OR_RETURN(auto surface, MakeSurface(request.surface));
    auto entry = std::make_shared<CachedSurface>();
    entry->id = id;
    entry->request = std::move(request);
    entry->surface = std::move(surface);
    entry->sheet = std::move(decoded.sheet);
    entry->flatten_ms = decoded.parts.flatten_ms;
    entry->bytes = EstimateBytes(*entry);
    return std::shared_ptr<const CachedSurface>(std::move(entry));
  }

  // Another replica holds the lock on `id`: its value, once the lock is
  // released, or nullptr after the tier's wait bound (or half of what is left
  // of this request's budget, whichever is less); then this replica flattens.
  std::shared_ptr<const CachedSurface> WaitForShared(const std::string& id,
                                                     const RequestClock& clock) {
    const SharedTierOptions& o = shared->options();
    const auto t0 = Clock::now();
    const double bound = std::min(o.wait_ms, clock.remaining_ms() / 2);
    const auto poll = std::chrono::duration<double, std::milli>(o.poll_ms);
    while (MsSince(t0) < bound) {
      std::this_thread::sleep_for(poll);
      if (shared->Exists(SheetLockKey(id)) && MsSince(t0) < bound) continue;
      auto e = FromShared(id);
      shared->CountLockWait(e != nullptr);
      return e;
    }
    shared->CountLockWait(false);
    return FromShared(id);
  }

  Result<std::shared_ptr<const CachedSurface>> Lookup(std::string_view id) {
    if (!proto::IsSurfaceIdShaped(id)) {
      return Status(ErrorCode::kNotFound,
                    "no surface has this id (ids are 32 hex digits from POST /v1/surfaces)", "id");
    }
    std::shared_ptr<const CachedSurface> found;
    if (shared == nullptr) {
      found = cache.Find(std::string(id));
    } else {  // a miss here reads the second level (once for concurrent callers)
      bool hit = false;
      auto fetched = cache.GetOrCompute(
          std::string(id),
          [&]() -> Result<std::shared_ptr<const CachedSurface>> {
            if (auto e = FromShared(std::string(id))) return e;
            return Status(ErrorCode::kNotFound, "not in the shared tier");
          },
          &hit);
      if (fetched.ok()) found = *fetched;
    }
    if (found == nullptr) {
      return Status(ErrorCode::kNotFound,
                    "no flattened surface with this id is cached here (it may have been evicted): "
                    "POST its description to /v1/surfaces again, or send it inline",
                    "id");
    }
    return found;
  }

  // The surface a deformation names: flattened (or from the cache) when it is
  // inline, looked up when it is named by id (then *hit).
  Result<std::shared_ptr<const CachedSurface>> SurfaceOf(const proto::DeformParams& params,
                                                         const RequestClock& clock, bool* hit) {
    *hit = false;
    if (params.surface) {
      auto flattened = Flattened(*params.surface, clock, hit);
      if (!flattened.ok()) return WithinBudget(clock, "flattening", flattened.status());
      return flattened;
    }
    auto found = Lookup(params.surface_id);
    if (!found.ok()) {
      const Status& s = found.status();
      return Status(s.code(), s.message(), "surface_id");
    }
    *hit = true;
    return found;
  }

  // The grid and the frame count against this server's limits.
  Status CheckFrames(const proto::AnimationRequest& request) const {
    SURFDEFORM_RETURN_IF_ERROR(CheckGrid(request.sampling));
    const int frames = request.animation.frames;
    const int limit = options.limits.max_animation_frames;
    if (frames > limit) {
      return Status::LimitExceeded("this server animates at most " + std::to_string(limit) +
                                       " frames, asked for " + std::to_string(frames),
                                   "animation.frames", limit, frames);
    }
    const SamplingOptions& s = request.sampling;
    return CheckMemory(kAnimationBytesPerFrameSample * frames * s.nu * s.nv,
                       options.limits.request_memory_bytes,
                       "flattening " + std::to_string(frames) + " frames of " +
                           std::to_string(s.nu) + " x " + std::to_string(s.nv),
                       "animation.frames");
  }

  // The sheets of an animation, from the cache or flattened now (within the
  // caller's slot: single-flight, so concurrent requests for one animation
  // share one flattening).
  Result<std::shared_ptr<const CachedAnimation>> FlattenedAnimation(
      const proto::AnimationRequest& request, const RequestClock& clock, int threads, bool* hit) {
    SURFDEFORM_RETURN_IF_ERROR(CheckFrames(request));
    const std::string id = proto::AnimationId(request);
    return animations.GetOrCompute(
        id,
        [&]() -> Result<std::shared_ptr<const CachedAnimation>> {
          const auto t0 = Clock::now();
          FlattenOptions flatten = request.flatten;
          flatten.threads = threads;
          flatten.time_budget_ms = clock.BudgetFor(options.limits.flatten_time_budget_ms);
          auto sheets = FlattenAnimation(request.animation, request.sampling, flatten);
          if (!sheets.ok()) {
            const Status& st = sheets.status();
            if (st.code() == ErrorCode::kDeadlineExceeded) return st;
            // The frame's surface is at fault: name the animation.
            return Status(st.code(), st.message(),
                          st.field().empty() ? std::string("animation") : st.field());
          }
          auto entry = std::make_shared<CachedAnimation>();
          entry->id = id;
          entry->request = request;
          entry->sheets = std::move(*sheets);
          entry->flatten_ms = MsSince(t0);
          entry->bytes = EstimateBytes(*entry);
          return std::shared_ptr<const CachedAnimation>(std::move(entry));
        },
        hit);
  }

  // A model on an animation: its sheets, one map per frame, and the model
  // placed on the first sheet and refined for every frame.
  struct AnimatedModel {
    std::shared_ptr<const CachedAnimation> entry;
    std::vector<SheetMap> maps;
    PreparedModel model;
    bool hit = false;
    double flatten_ms = 0.0;
    double subdivide_ms = 0.0;
  };

  Result<AnimatedModel> PrepareAnimated(const proto::AnimationRequest& request, Mesh&& mesh,
                                        PlacementOptions placement, SubdivisionOptions subdivision,
                                        const RequestClock& clock, int threads) {
    AnimatedModel a;
    const auto t0 = Clock::now();
    auto entry = FlattenedAnimation(request, clock, threads, &a.hit);
    if (!entry.ok()) return WithinBudget(clock, "flattening", entry.status());
    a.entry = *entry;
    a.flatten_ms = MsSince(t0);
    SURFDEFORM_RETURN_IF_ERROR(clock.Check("flattening"));
    const auto t1 = Clock::now();
    const AnimatedSheets& sheets = a.entry->sheets;
    a.maps.reserve(sheets.sheets.size());
    for (size_t k = 0; k < sheets.sheets.size(); ++k) {
      a.maps.emplace_back(*sheets.surfaces[k], sheets.sheets[k]);
    }
    std::vector<const SheetMap*> maps;
    for (const SheetMap& m : a.maps) maps.push_back(&m);
    placement.threads = threads;
    subdivision.threads = threads;
    subdivision.max_vertices =
        CountWithin(options.limits.request_memory_bytes, kSubdivisionBytesPerVertex,
                    options.limits.max_output_vertices);
    subdivision.max_triangles = options.limits.max_output_triangles;
    subdivision.time_budget_ms = clock.BudgetFor(options.limits.request_time_budget_ms);
    auto model = PrepareModel(maps, std::move(mesh), placement, subdivision);
    if (!model.ok()) return WithinBudget(clock, "subdivision", model.status());
    a.model = std::move(*model);
    a.subdivide_ms = MsSince(t1);
    SURFDEFORM_RETURN_IF_ERROR(clock.Check("subdivision"));
    return a;
  }

  static PlacementOptions PlacementFor(const PlacementOptions& given, const ImportedMesh& m) {
    PlacementOptions p = given;
    p.y_up_input = m.format == MeshFormat::kGlb || m.format == MeshFormat::kGltf;
    return p;
  }

  // POST /v1/deform with an animation: frame k alone, the same computation
  // as frame k of POST /v1/animate.
  Result<Reply> DeformFrame(const proto::DeformParams& params, ImportedMesh imported,
                            proto::OutputFormat format, const RequestClock& clock, int threads,
                            double parse_ms) {
    const PlacementOptions placement = PlacementFor(params.placement, imported);
    SURFDEFORM_ASSIGN_OR_RETURN(
        AnimatedModel a, PrepareAnimated(*params.animation, std::move(imported.mesh), placement,
                                         params.subdivision, clock, threads));
    const auto t2 = Clock::now();
    const size_t k = static_cast<size_t>(params.frame);
    DeformExtras extras;
    extras.distortion = params.output.distortion;
    PlacementOptions p = placement;
    p.threads = threads;
    SURFDEFORM_ASSIGN_OR_RETURN(DeformResult deformed,
                                DeformPrepared(a.maps[k], a.model, k, p, extras));
    const double deform_ms = MsSince(t2);
    const FrameFlattening& f = a.entry->sheets.frames[k];
    json stats = DeformStatsHeader(a.entry->id, f.quality, a.hit, format, imported, deformed.stats);
    stats["animation"] = {
        {"frame", params.frame}, {"frames", params.animation->animation.frames}, {"time", f.time}};
    return MeshReply(deformed.mesh, params.output, format, imported, a.hit,
                     {{"parse", parse_ms},
                      {"flatten", a.flatten_ms},
                      {"deform", deform_ms},
                      {"subdivide", a.subdivide_ms}},
                     stats);
  }

  const ServiceOptions options;
  const std::shared_ptr<SharedTier> shared;  // may be null
  SingleFlightCache<CachedSurface> cache;
  SingleFlightCache<CachedAnimation> animations;
  Admission admission;
  // Placements and footprints of models that come back, by surface, options
  // and positions.
  PlacementMemo placements{kPlacementMemoEntries, options.limits.footprint_memo_bytes};
};

Service::Service(ServiceOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
Service::~Service() = default;

const ServiceLimits& Service::limits() const { return impl_->options.limits; }
CacheStats Service::cache_stats() const { return impl_->cache.stats(); }
PlacementMemoStats Service::placement_memo_stats() const { return impl_->placements.stats(); }
AdmissionStats Service::admission_stats() const { return impl_->admission.stats(); }
bool Service::Saturated() const { return impl_->admission.Full(); }
int Service::RetryAfterSeconds() const { return impl_->admission.RetryAfterSeconds(); }
SharedTierStats Service::shared_tier_stats() const {
  return impl_->shared != nullptr ? impl_->shared->stats() : SharedTierStats{};
}

Result<Reply> Service::CreateSurface(std::string_view body) {
  // No ticket up front: parsing is bounded by the body's size and depth, and
  // only a flattening that this request must run itself is admitted.
  const RequestClock clock(impl_->options.limits.request_time_budget_ms);
  const auto t0 = Clock::now();
  SURFDEFORM_ASSIGN_OR_RETURN(
      auto parsed, proto::ParseRequestJson(body, impl_->options.limits.max_json_depth, "body"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto request, proto::ParseSurfaceRequest(parsed));
  const double parse_ms = MsSince(t0);
  SURFDEFORM_RETURN_IF_ERROR(clock.Check("parsing"));
  const auto t1 = Clock::now();
  bool hit = false;
  auto entry = impl_->Flattened(request, clock, &hit, /*admit=*/true);
  if (!entry.ok() && entry.status().code() == ErrorCode::kUnavailable) {
    // The flattening this request waited on was refused (its caller found no
    // room): try once on this request's own account.
    entry = impl_->Flattened(request, clock, &hit, /*admit=*/true);
  }
  if (!entry.ok()) return WithinBudget(clock, "flattening", entry.status());
  Reply reply;
  reply.cache_hit = hit;
  reply.surface_id = (*entry)->id;
  json summary = SheetSummary(**entry, hit);
  SURFDEFORM_ASSIGN_OR_RETURN(reply.body, DumpFinite(summary, "reply"));
  reply.content_type = "application/json";
  reply.timings = {{"parse", parse_ms}, {"flatten", MsSince(t1)}};
  reply.stats_json = Dump({{"surface_id", (*entry)->id}, {"cached", hit}});
  reply.etag = proto::Sha256Hex(reply.body, 32);
  return reply;
}

Result<Reply> Service::GetSurface(std::string_view id) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto entry, impl_->Lookup(id));
  const CachedSurface& s = *entry;
  json j = SheetSummary(s, true);
  j["request"] = proto::CanonicalJson(s.request);
  json points = json::array();
  json flat = json::array();
  for (const Vec3& p : s.sheet.points) points.push_back({p.x(), p.y(), p.z()});
  for (const Vec2& p : s.sheet.flat) flat.push_back({p.x(), p.y()});
  j["points"] = std::move(points);
  j["flat"] = std::move(flat);
  Reply reply;
  reply.cache_hit = true;
  SURFDEFORM_ASSIGN_OR_RETURN(reply.body, DumpFinite(j, "reply"));
  reply.content_type = "application/json";
  reply.etag = proto::Sha256Hex(reply.body, 32);
  return reply;
}

Result<Reply> Service::GetSurfaceSvg(std::string_view id) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto entry, impl_->Lookup(id));
  Reply reply;
  reply.cache_hit = true;
  reply.body = FlatSheetSvg(entry->sheet, "surfdeform flat sheet " + entry->id);
  reply.content_type = "image/svg+xml";
  reply.etag = proto::Sha256Hex(reply.body, 32);
  return reply;
}

Result<Reply> Service::MapOnSurface(std::string_view id, std::string_view body) {
  const ServiceLimits& limits = impl_->options.limits;
  const RequestClock clock(limits.request_time_budget_ms);
  const auto t0 = Clock::now();
  SURFDEFORM_ASSIGN_OR_RETURN(auto parsed,
                              proto::ParseRequestJson(body, limits.max_json_depth, "body"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto request, proto::ParseMapRequest(parsed, kMapLimits));
  SURFDEFORM_ASSIGN_OR_RETURN(auto entry, impl_->Lookup(id));
  const double parse_ms = MsSince(t0);
  // Up to a million surface evaluations: a slot like any other work.
  SURFDEFORM_ASSIGN_OR_RETURN(auto ticket, impl_->admission.Enter(clock.remaining_ms()));
  const auto t1 = Clock::now();
  const SheetMap map(*entry->surface, entry->sheet);
  std::vector<std::vector<SheetMark>> marks;
  switch (request.kind) {
    case proto::MapRequest::Kind::kPoints:
      marks.emplace_back();
      for (const Vec2& p : request.points) marks[0].push_back(MarkAt(map, p));
      break;
    case proto::MapRequest::Kind::kSurfacePoints:
      marks.emplace_back();
      for (const Vec3& p : request.surface_points) marks[0].push_back(MarkNearest(map, p));
      break;
    case proto::MapRequest::Kind::kPolylines: {
      PolylineOptions o = request.polyline;
      o.max_points = CountWithin(impl_->options.limits.request_memory_bytes,
                                 kMapBytesPerOutputPoint, kMaxMapOutputPoints);
      SURFDEFORM_ASSIGN_OR_RETURN(marks, ResamplePolylines(map, request.polylines, o));
      break;
    }
  }
  Reply reply;
  reply.cache_hit = true;
  reply.surface_id = entry->id;
  SURFDEFORM_ASSIGN_OR_RETURN(reply.body,
                              DumpFinite(proto::MapResponseJson(request.kind, marks), "reply"));
  reply.content_type = "application/json";
  reply.timings = {{"parse", parse_ms}, {"map", MsSince(t1)}};
  reply.etag = proto::Sha256Hex(reply.body, 32);
  return reply;
}

Result<Reply> Service::Deform(const DeformRequest& request) {
  const ServiceLimits& limits = impl_->options.limits;
  const RequestClock clock(limits.request_time_budget_ms);
  SURFDEFORM_ASSIGN_OR_RETURN(auto ticket, impl_->admission.Enter(clock.remaining_ms()));
  const int threads = impl_->ThreadsFor(ticket);
  const auto t0 = Clock::now();
  SURFDEFORM_ASSIGN_OR_RETURN(
      auto parsed, proto::ParseRequestJson(request.params, limits.max_json_depth, "params"));
  const std::string& routed = request.routed_surface_id;
  if (!routed.empty() && parsed.is_object() && !parsed.contains("surface") &&
      !parsed.contains("surface_id")) {
    parsed["surface_id"] = routed;
  }
  // Errors name their fields by JSON path in the parameters.
  SURFDEFORM_ASSIGN_OR_RETURN(auto params, proto::ParseDeformParams(parsed));
  if (!routed.empty()) {
    const std::string named =
        params.surface ? proto::SurfaceId(*params.surface) : params.surface_id;
    if (named != routed) {
      return Status(ErrorCode::kMalformed,
                    "the X-Surfdeform-Surface-Id header (or surface_id query parameter) names "
                    "surface " +
                        routed + " but the parameters name " + named +
                        ": they must agree, since load balancers route by the header",
                    "X-Surfdeform-Surface-Id");
    }
  }
  SURFDEFORM_ASSIGN_OR_RETURN(auto format,
                              ChooseOutputFormat(params.output.format, request.accept));
  SURFDEFORM_RETURN_IF_ERROR(CheckDistortionFormat(params.output, format));
  if (request.mesh.empty()) {
    return Status(ErrorCode::kMalformed, "the request carries no mesh", "mesh");
  }
  faults::MaybeFailAllocation();  // the test build's fault point; nothing in production
  SURFDEFORM_ASSIGN_OR_RETURN(auto imported, ImportMesh(request.mesh, ImportLimitsOf(limits)));
  const double parse_ms = MsSince(t0);
  SURFDEFORM_RETURN_IF_ERROR(clock.Check("parsing"));
  if (params.animation) {
    return impl_->DeformFrame(params, std::move(imported), format, clock, threads, parse_ms);
  }

  const auto t1 = Clock::now();
  bool hit = false;
  SURFDEFORM_ASSIGN_OR_RETURN(const std::shared_ptr<const CachedSurface> entry,
                              impl_->SurfaceOf(params, clock, &hit));
  const double flatten_ms = MsSince(t1);
  SURFDEFORM_RETURN_IF_ERROR(clock.Check("flattening"));

  const auto t2 = Clock::now();
  PlacementOptions placement = params.placement;
  placement.threads = threads;
  placement.y_up_input =
      imported.format == MeshFormat::kGlb || imported.format == MeshFormat::kGltf;
  SubdivisionOptions subdivision = params.subdivision;
  subdivision.threads = threads;
  subdivision.max_vertices = CountWithin(limits.request_memory_bytes, kSubdivisionBytesPerVertex,
                                         limits.max_output_vertices);
  subdivision.max_triangles = limits.max_output_triangles;
  subdivision.time_budget_ms = clock.BudgetFor(limits.request_time_budget_ms);
  DeformExtras extras;
  extras.distortion = params.output.distortion;
  const PlacementMemo::Key placed_key =
      impl_->placements.KeyOf(entry->id, placement, imported.mesh.positions);
  const std::optional<PlacementMemo::Entry> known = impl_->placements.Find(placed_key);
  if (known) extras.placement = &known->placement;
  if (known && known->footprint) {
    extras.footprint = known->footprint.get();
  } else {
    extras.record_footprint = true;
  }
  std::optional<PlacementMemo::Key> subdivision_key;
  if (subdivision.mode != SubdivisionMode::kOff) {
    subdivision_key = impl_->placements.SubdivisionKeyOf(subdivision, imported.mesh.triangles);
    if (known) extras.unrefined = impl_->placements.UnrefinedVerdict(*known, *subdivision_key);
  }
  auto deformed = DeformMesh(*entry->surface, entry->sheet, std::move(imported.mesh), placement,
                             subdivision, extras);
  if (!deformed.ok()) return WithinBudget(clock, "subdivision", deformed.status());
  if (!known || !known->footprint) {
    std::shared_ptr<const SheetFootprint> footprint;
    if (!deformed->footprint.location.empty()) {
      footprint = std::make_shared<const SheetFootprint>(std::move(deformed->footprint));
    }
    impl_->placements.Store(placed_key, deformed->placement, std::move(footprint));
  }
  const bool subdivision_skipped = extras.unrefined != nullptr;
  if (deformed->unrefined && !subdivision_skipped && subdivision_key) {
    impl_->placements.NoteUnrefined(placed_key, *subdivision_key, deformed->stats.subdivision);
  }
  const double subdivide_ms = deformed->stats.subdivide_ms;
  const double deform_ms = MsSince(t2) - subdivide_ms;
  SURFDEFORM_RETURN_IF_ERROR(clock.Check("deformation"));

  return MeshReply(deformed->mesh, params.output, format, imported, hit,
                   {{"parse", parse_ms},
                    {"flatten", flatten_ms},
                    {"deform", deform_ms},
                    {"subdivide", subdivide_ms}},
                   DeformStatsHeader(entry->id, entry->sheet.quality, hit, format, imported,
                                     deformed->stats, known.has_value(), subdivision_skipped));
}

Result<Reply> Service::Animate(const DeformRequest& request) {
  const ServiceLimits& limits = impl_->options.limits;
  const RequestClock clock(limits.request_time_budget_ms);
  SURFDEFORM_ASSIGN_OR_RETURN(auto ticket, impl_->admission.Enter(clock.remaining_ms()));
  const int threads = impl_->ThreadsFor(ticket);
  const auto t0 = Clock::now();
  SURFDEFORM_ASSIGN_OR_RETURN(
      auto parsed, proto::ParseRequestJson(request.params, limits.max_json_depth, "params"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto params, proto::ParseAnimateParams(parsed));
  SURFDEFORM_RETURN_IF_ERROR(impl_->CheckFrames(params.animation));
  SURFDEFORM_RETURN_IF_ERROR(AcceptGlbOnly(request.accept));
  if (request.mesh.empty()) {
    return Status(ErrorCode::kMalformed, "the request carries no mesh", "mesh");
  }
  SURFDEFORM_ASSIGN_OR_RETURN(auto imported, ImportMesh(request.mesh, ImportLimitsOf(limits)));
  const double parse_ms = MsSince(t0);
  SURFDEFORM_RETURN_IF_ERROR(clock.Check("parsing"));
  const PlacementOptions placement = Impl::PlacementFor(params.placement, imported);
  // Checked before any work on the input's count, and again after the
  // subdivision on the output's.
  auto check_frame_vertices = [&limits](size_t frames, size_t vertices) -> Status {
    if (frames * vertices <= limits.max_animation_frame_vertices) return Status::Ok();
    return Status::LimitExceeded(
        std::to_string(frames) + " frames of " + std::to_string(vertices) +
            " vertices are more than this server animates in one request (" +
            std::to_string(limits.max_animation_frame_vertices) +
            " frame vertices); ask for fewer frames or a smaller model",
        "animation.frames", static_cast<double>(limits.max_animation_frame_vertices),
        static_cast<double>(frames * vertices));
  };
  SURFDEFORM_RETURN_IF_ERROR(check_frame_vertices(
      static_cast<size_t>(params.animation.animation.frames), imported.mesh.positions.size()));
  SURFDEFORM_ASSIGN_OR_RETURN(
      Impl::AnimatedModel a, impl_->PrepareAnimated(params.animation, std::move(imported.mesh),
                                                    placement, params.subdivision, clock, threads));
  const size_t frames = a.maps.size();
  const size_t vertices = a.model.mesh.positions.size();
  SURFDEFORM_RETURN_IF_ERROR(check_frame_vertices(frames, vertices));

  const auto t2 = Clock::now();
  MorphAnimation anim;
  anim.base = &a.model.mesh;
  anim.fps = params.animation.animation.fps;
  anim.positions.resize(frames);
  if (a.model.need_frame && !a.model.mesh.normals.empty()) anim.normals.resize(frames);
  PlacementOptions p = placement;
  p.threads = threads;
  DeformExtras extras;
  extras.geometry_only = true;
  DeformStats first_stats;
  for (size_t k = 0; k < frames; ++k) {
    auto frame = DeformPrepared(a.maps[k], a.model, k, p, extras);
    if (!frame.ok()) {
      const Status& st = frame.status();
      return Status(st.code(), "frame " + std::to_string(k) + ": " + st.message(), st.field());
    }
    if (k == 0) first_stats = frame->stats;
    const Mesh& m = frame->mesh;
    anim.positions[k].resize(m.positions.size());
    for (size_t v = 0; v < m.positions.size(); ++v) {
      anim.positions[k][v] = m.positions[v].cast<float>();
    }
    if (!anim.normals.empty()) {
      anim.normals[k].resize(m.normals.size());
      for (size_t v = 0; v < m.normals.size(); ++v) anim.normals[k][v] = m.normals[v].cast<float>();
    }
    SURFDEFORM_RETURN_IF_ERROR(clock.Check("deformation"));
  }
  const double deform_ms = MsSince(t2);

  const auto t3 = Clock::now();
  AnimationGlbOptions glb;
  glb.compression = params.output.compression.value_or(AnimationCompression::kMeshopt);
  glb.look.materials = imported.materials;
  glb.look.look = imported.look;
  glb.threads = threads;
  SURFDEFORM_ASSIGN_OR_RETURN(std::string bytes, WriteAnimationGlb(anim, glb));
  if (bytes.size() > limits.max_animation_bytes) {
    return Status::LimitExceeded("the animation's GLB would be " + std::to_string(bytes.size()) +
                                     " bytes, more than this server returns (" +
                                     std::to_string(limits.max_animation_bytes) + ")",
                                 "animation.frames",
                                 static_cast<double>(limits.max_animation_bytes),
                                 static_cast<double>(bytes.size()));
  }
  const double encode_ms = MsSince(t3);

  const AnimatedSheets& sheets = a.entry->sheets;
  json per_frame = json::array();
  long long warm_iterations = 0;
  for (const FrameFlattening& f : sheets.frames) {
    per_frame.push_back({{"time", f.time},
                         {"warm", f.warm},
                         {"paths_reused", f.reused_paths},
                         {"stress", f.quality.stress},
                         {"iterations", f.quality.iterations},
                         {"folded_cells", f.quality.folded_cells},
                         {"ms", f.quality.total_ms}});
    if (f.warm) warm_iterations += f.quality.iterations;
  }
  // Frame 0 starts cold: what the others would have taken each, at most.
  const long long cold = sheets.frames.front().quality.iterations;
  json stats = {
      {"animation_id", a.entry->id},
      {"cached", a.hit},
      {"frames", frames},
      {"fps", anim.fps},
      {"vertices", vertices},
      {"triangles", a.model.mesh.triangles.size()},
      {"compression", NameOf<AnimationCompression>(kAnimationCompressions, glb.compression)},
      {"input_format", MeshFormatName(imported.format)},
      {"subdivision", proto::SubdivisionStatsJson(a.model.subdivision)},
      {"subdivision_passes", a.model.subdivision_passes},
      {"placement", proto::DeformStatsJson(first_stats)},
      {"flatten",
       {{"iterations_first", cold},
        {"iterations_warm_mean",
         frames > 1 ? static_cast<double>(warm_iterations) / static_cast<double>(frames - 1) : 0.0},
        {"iterations_saved_estimate",
         std::max(0LL, cold * static_cast<long long>(frames - 1) - warm_iterations)},
        {"each", std::move(per_frame)}}},
      {"warnings", imported.warnings}};
  Reply reply;
  reply.cache_hit = a.hit;
  reply.body = std::move(bytes);
  reply.content_type = "model/gltf-binary";
  reply.timings = {{"parse", parse_ms},
                   {"flatten", a.flatten_ms},
                   {"subdivide", a.subdivide_ms},
                   {"deform", deform_ms},
                   {"encode", encode_ms}};
  SURFDEFORM_ASSIGN_OR_RETURN(reply.stats_json, StatsHeader(std::move(stats)));
  reply.etag = proto::Sha256Hex(reply.body, 32);
  return reply;
}

std::string Service::InfoJson() const {
  const ServiceLimits& l = impl_->options.limits;
  json j = {
      {"name", "surfdeform"},
      {"version", SURFDEFORM_VERSION},
      {"limits",
       {{"max_body_bytes", l.max_body_bytes},
        {"max_vertices", l.max_vertices},
        {"max_triangles", l.max_triangles},
        {"max_grid_side", l.max_grid_side},
        {"max_output_vertices",
         CountWithin(l.request_memory_bytes, kSubdivisionBytesPerVertex, l.max_output_vertices)},
        {"max_output_triangles", l.max_output_triangles},
        {"max_json_depth", l.max_json_depth},
        {"max_in_flight", l.max_in_flight},
        {"max_queued", l.max_queued},
        {"queue_timeout_ms", l.queue_timeout_ms},
        {"flatten_time_budget_ms", l.flatten_time_budget_ms},
        {"request_time_budget_ms", l.request_time_budget_ms},
        {"cache_bytes", l.cache_bytes},
        {"max_map_points", kMapLimits.max_points},
        {"max_map_surface_points", kMapLimits.max_surface_points},
        {"max_map_output_points",
         CountWithin(l.request_memory_bytes, kMapBytesPerOutputPoint, kMaxMapOutputPoints)},
        {"max_animation_frames", l.max_animation_frames},
        {"max_animation_frame_vertices", l.max_animation_frame_vertices},
        {"max_animation_bytes", l.max_animation_bytes},
        {"request_memory_bytes", l.request_memory_bytes}}},
      {"input_formats", {"glb", "gltf", "drc", "obj", "ply", "stl", "off"}},
      {"output_formats", NamesOf<proto::OutputFormat>(proto::kOutputFormats)},
      {"surface_kinds", NamesOf<proto::SurfaceKind>(proto::kSurfaceKinds)},
      {"flatten_methods", NamesOf<FlattenMethod>(kFlattenMethods)},
      {"subdivision_modes", NamesOf<SubdivisionMode>(kSubdivisionModes)}};
  // Every named choice of the request, by its field: {name, description}.
  json& enums = j["enums"];
  auto publish = [&enums](const char* field, const auto& table) {
    for (const auto& e : table) {
      enums[field].push_back({{"name", e.name}, {"description", e.description}});
    }
  };
  publish("surface.kind", proto::kSurfaceKinds);
  publish("flatten.method", kFlattenMethods);
  publish("placement.up", kUpAxes);
  publish("placement.rigid", kRigidModes);
  publish("placement.anchor", kAnchorModes);
  publish("placement.outside", kOutsideModes);
  publish("output.format", proto::kOutputFormats);
  publish("subdivision.mode", kSubdivisionModes);
  publish("animation.interpolation", kInterpolations);
  publish("output.compression", kAnimationCompressions);
  for (const auto& e : kErrorCodes) {  // problem+json's "code"
    if (e.value != ErrorCode::kOk)
      enums["problem.code"].push_back({{"name", e.name}, {"description", e.description}});
  }
  return Dump(j);
}

}  // namespace surfdeform
