// Over ~600 lines: one Service::Impl, the short sequence of calls each route
// makes into the rooms (surface_store, request_work, replies, limit_checks,
// placement_memo, answer_cache), which share its state.
#include "service/service.hpp"

#include <chrono>
#include <functional>

#include "engine/animation/animation.hpp"
#include "engine/common/elapsed.hpp"
#include "engine/common/parallel.hpp"
#include "engine/deform/deform.hpp"
#include "engine/flatten/seam_extension.hpp"
#include "engine/sheet/sheet_field.hpp"
#include "engine/sheet/sheet_marks.hpp"
#include "meshio/animation_glb.hpp"
#include "meshio/mesh_import.hpp"
#include "proto/answer_key.hpp"
#include "proto/api.hpp"
#include "proto/map_api.hpp"
#include "proto/text_json.hpp"
#include "service/answer_cache.hpp"
#include "service/content_coding.hpp"
#include "service/engine_options.hpp"
#include "service/field_encoding.hpp"
#include "service/flat_sheet_svg.hpp"
#include "service/font_store.hpp"
#include "service/limit_checks.hpp"
#include "service/meshopt_orders.hpp"
#include "service/model_store.hpp"
#include "service/output_negotiation.hpp"
#include "service/part_replies.hpp"
#include "service/placement_memo.hpp"
#include "service/replies.hpp"
#include "service/request_work.hpp"
#include "service/surface_store.hpp"
#include "service/text_models.hpp"
#include "service/warm_start.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// A field's lattice points per side when the request names none.
constexpr int kDefaultFieldSide = 64;

// Placements the memo keeps (~250 bytes each with their index).
constexpr size_t kPlacementMemoEntries = 1024;

// A model on an animation: its sheets, one map per frame, and the model
// placed on every frame's sheet and refined for every frame.
struct AnimatedModel {
  std::shared_ptr<const StoredAnimation> entry;
  std::vector<SheetMap> maps;
  PreparedModel model;
  bool hit = false;
  double flatten_ms = 0.0;
  double subdivide_ms = 0.0;
};

// The route's surface id and the parameters' must agree, since load
// balancers route by the former; with none in the parameters it names the
// surface.
void RouteSurfaceId(const std::string& routed, json* parsed) {
  if (!routed.empty() && parsed->is_object() && !parsed->contains("surface") &&
      !parsed->contains("surface_id")) {
    (*parsed)["surface_id"] = routed;
  }
}

Status CheckRoutedSurface(const std::string& routed, const proto::DeformParams& params) {
  if (routed.empty()) return Status::Ok();
  const std::string named = params.surface ? proto::SurfaceId(*params.surface) : params.surface_id;
  if (named == routed) return Status::Ok();
  return Status(ErrorCode::kMalformed,
                "the X-Surfdeform-Surface-Id header (or surface_id query parameter) names "
                "surface " +
                    routed + " but the parameters name " + named +
                    ": they must agree, since load balancers route by the header",
                "X-Surfdeform-Surface-Id");
}

// Answers whose own encoding leaves redundancy for gzip: all but Draco's.
bool Compresses(const proto::OutputOptions& output, proto::OutputFormat format) {
  if (format == proto::OutputFormat::kDrc) return false;
  return format != proto::OutputFormat::kGlb ||
         GlbEncodingOf(output, format) != GlbEncoding::kDraco;
}

// The body gzipped beside it, where that saves at least a tenth.
void AddGzip(Reply* reply) {
  std::string gz = GzipFast(reply->body);
  if (!gz.empty() && gz.size() * 10 < reply->body.size() * 9) reply->gzip_body = std::move(gz);
}

// A request's mesh comes by model_id or in its body, not both.
Status CheckOneMesh(const std::string& model_id, std::string_view body) {
  if (model_id.empty() || body.empty()) return Status::Ok();
  return Status(ErrorCode::kMalformed,
                "the parameters name a model_id and the request carries a mesh too: send "
                "one of them",
                "model_id");
}

}  // namespace

struct Service::Impl {
  explicit Impl(ServiceOptions o)
      : options(Normalised(std::move(o))),
        store(options.limits, options.engine_threads, options.shared_tier),
        models(options.limits, options.shared_tier),
        fonts(options.limits, options.shared_tier),
        admission(AdmissionOptions{options.limits.max_in_flight, options.limits.max_queued,
                                   options.limits.queue_timeout_ms, Cores()}),
        parse_memory(options.limits.max_json_elements_in_flight) {
    store.UseModels(&models);
  }

  static int Cores() { return ResolveThreads(0); }  // one per core

  static ServiceOptions Normalised(ServiceOptions o) {
    if (o.limits.max_in_flight <= 0) o.limits.max_in_flight = Cores();
    if (o.limits.max_queued < 0) o.limits.max_queued = 4 * Cores();
    return o;
  }

  // The surface a deformation names: flattened (or from the store) when it
  // is inline, from `warm`'s sheet where it names one (an edit: its paths
  // kept for the next), looked up when it is named by id (then *hit).
  Result<std::shared_ptr<const StoredSurface>> SurfaceOf(const proto::DeformParams& params,
                                                         const WarmStart& warm,
                                                         const RequestClock& clock, bool* hit) {
    *hit = false;
    if (params.surface) {
      const EditStart edit{!warm.from.empty(), warm.entry.get()};
      auto flattened = store.Flattened(*params.surface, clock, hit, nullptr, edit);
      if (!flattened.ok()) return WithinBudget(clock, "flattening", flattened.status());
      return flattened;
    }
    auto found = store.Find(params.surface_id);
    if (!found.ok()) {
      const Status& s = found.status();
      return Status(s.code(), s.message(), "surface_id");
    }
    *hit = true;
    return found;
  }

  // The request's mesh: the uploaded model it names (a copy: the work
  // consumes it), or its body imported. Ends the parse phase.
  template <typename Params>
  Result<ImportedMesh> MeshOf(const Params& params, std::string_view body, RequestWork& work) {
    if (params.text) {
      SURFDEFORM_RETURN_IF_ERROR(CheckTextAlone(params.text, body));
      SURFDEFORM_ASSIGN_OR_RETURN(auto font, fonts.Find(params.text->font, "text.font"));
      SURFDEFORM_ASSIGN_OR_RETURN(
          ImportedMesh made,
          MakeTextMesh(*params.text, *font, fonts, options.limits.font, work.clock().cancel()));
      SURFDEFORM_RETURN_IF_ERROR(work.EndParse());
      return made;
    }
    return MeshOf(params.model_id, body, work);
  }
  Result<ImportedMesh> MeshOf(const std::string& model_id, std::string_view body,
                              RequestWork& work) {
    if (model_id.empty()) return work.Import(body);
    SURFDEFORM_RETURN_IF_ERROR(CheckOneMesh(model_id, body));
    SURFDEFORM_ASSIGN_OR_RETURN(auto model, models.Find(model_id));
    ImportedMesh copy = model->imported;
    SURFDEFORM_RETURN_IF_ERROR(work.EndParse());
    return copy;
  }

  // The model's part of an answer's key: an upload's id, the body's, or a
  // text's (its settings and its font's content).
  template <typename Params>
  Result<std::string> ModelKeyOf(const Params& params, std::string_view body) {
    if (params.text) {
      SURFDEFORM_ASSIGN_OR_RETURN(auto font, fonts.Find(params.text->font, "text.font"));
      return TextModelKey(*params.text, font->id);
    }
    return params.model_id.empty() ? proto::ModelId(body) : params.model_id;
  }

  // The field of a stored surface, with a slot from admission (up to
  // max_field_side^2 surface evaluations).
  Result<SheetField> FieldOf(const StoredSurface& entry, int side, RequestWork& work) {
    SURFDEFORM_RETURN_IF_ERROR(work.Admit(admission, options.engine_threads));
    return SampleSheetField(*entry.map, side, work.threads());
  }

  Result<AnimatedModel> PrepareAnimated(const proto::AnimationRequest& request, Mesh&& mesh,
                                        const DeformOptions& asked, const RequestWork& work) {
    const RequestClock& clock = work.clock();
    AnimatedModel a;
    const auto t0 = Clock::now();
    auto entry = store.FlattenedAnimation(request, clock, work.threads(), &a.hit);
    if (!entry.ok()) return WithinBudget(clock, "flattening", entry.status());
    a.entry = *entry;
    a.flatten_ms = MsSince(t0);
    SURFDEFORM_RETURN_IF_ERROR(clock.Check("flattening"));
    const auto t1 = Clock::now();
    const AnimatedSheets& sheets = a.entry->sheets;
    a.maps.reserve(sheets.sheets.size());
    // One grid for every frame: across the seam as far as every frame
    // allows, and not at all unless every frame closes (a can that opens).
    int seam = -1;
    for (size_t k = 0; k < sheets.sheets.size(); ++k) {
      const int allowed = SeamColumns(*sheets.surfaces[k], sheets.sheets[k]);
      seam = seam < 0 ? allowed : std::min(seam, allowed);
    }
    for (size_t k = 0; k < sheets.sheets.size(); ++k) {
      a.maps.emplace_back(*sheets.surfaces[k], sheets.sheets[k], std::max(seam, 0));
    }
    std::vector<const SheetMap*> maps;
    for (const SheetMap& m : a.maps) maps.push_back(&m);
    DeformOptions deform = asked;
    deform.subdivision = SubdivisionFor(asked.subdivision, options.limits, work);
    const size_t frames = sheets.sheets.size();
    const int threads = ResolveThreads(deform.subdivision.threads);
    deform.subdivision.max_vertices = MaxAnimationOutputVertices(options.limits, frames, threads);
    auto model = PrepareModel(maps, std::move(mesh), deform);
    if (!model.ok()) {
      return WithinBudget(
          clock, "subdivision",
          AnimationSubdivisionError(options.limits, frames, threads, model.status()));
    }
    a.model = std::move(*model);
    a.subdivide_ms = MsSince(t1);
    SURFDEFORM_RETURN_IF_ERROR(clock.Check("subdivision"));
    return a;
  }

  // POST /v1/deform on a sheet: the model placed, refined and mapped, and
  // its answer encoded.
  Result<Reply> DeformOnSheet(const proto::DeformParams& params, const StoredSurface& entry,
                              bool hit, proto::OutputFormat format, ImportedMesh imported,
                              const RequestWork& work, double flatten_ms, std::string etag) {
    const ServiceLimits& limits = options.limits;
    const auto t2 = Clock::now();
    DeformOptions deform;
    deform.placement = PlacementFor(params.placement, imported, work.threads());
    deform.subdivision = SubdivisionFor(params.subdivision, limits, work);
    deform.distortion = params.output.distortion;
    PlacementMemo::Use memo(placements, entry.id, deform, imported.mesh);
    auto deformed = surfdeform::Deform(*entry.map, std::move(imported.mesh), deform, &memo);
    if (!deformed.ok()) return WithinBudget(work.clock(), "subdivision", deformed.status());
    const double subdivide_ms = deformed->stats.subdivide_ms;
    const double deform_ms = MsSince(t2) - subdivide_ms;
    SURFDEFORM_RETURN_IF_ERROR(work.clock().Check("deformation"));
    SURFDEFORM_ASSIGN_OR_RETURN(EncodeContext encode,
                                EncodeContextFor(deformed->mesh, params.output, format, work));
    encode.etag = std::move(etag);
    auto stats =
        DeformReplyStatsOf(entry.id, entry.sheet.quality, hit, format, imported, deformed->stats);
    stats->placement_reused = memo.placement_reused();
    stats->subdivision_reused = memo.subdivision_reused();
    return MeshReply(deformed->mesh, params.output, format, imported, hit,
                     {{"parse", work.parse_ms()},
                      {"flatten", flatten_ms},
                      {"deform", deform_ms},
                      {"subdivide", subdivide_ms}},
                     std::move(stats), encode);
  }

  // How this request's answer is encoded: on its ticket's threads (more
  // than one only when cores are idle), a large Draco GLB in pieces, a
  // meshopt one in the vertex order kept for its topology.
  Result<EncodeContext> EncodeContextFor(const Mesh& mesh, const proto::OutputOptions& output,
                                         proto::OutputFormat format, const RequestWork& work) {
    EncodeContext encode;
    encode.threads = work.threads();
    encode.glb_split_vertices = options.limits.glb_split_vertices;
    const GlbEncoding glb = GlbEncodingOf(output, format);
    if (format == proto::OutputFormat::kGlb &&
        (glb == GlbEncoding::kMeshopt || glb == GlbEncoding::kQuantized)) {
      SURFDEFORM_ASSIGN_OR_RETURN(encode.meshopt_order, orders.For(mesh));
    }
    return encode;
  }

  // POST /v1/deform with an animation: frame k alone, the same computation
  // as frame k of POST /v1/animate.
  Result<Reply> DeformFrame(const proto::DeformParams& params, ImportedMesh imported,
                            proto::OutputFormat format, const RequestWork& work, std::string etag) {
    DeformOptions deform;
    deform.placement = PlacementFor(params.placement, imported, work.threads());
    deform.subdivision = WithRunDefaults<SubdivisionOptions>(params.subdivision);
    deform.distortion = params.output.distortion;
    SURFDEFORM_ASSIGN_OR_RETURN(
        AnimatedModel a,
        PrepareAnimated(*params.animation, std::move(imported.mesh), deform, work));
    const auto t2 = Clock::now();
    const size_t k = static_cast<size_t>(params.frame);
    SURFDEFORM_ASSIGN_OR_RETURN(DeformResult deformed,
                                DeformPrepared(a.maps[k], a.model, k, deform));
    const double deform_ms = MsSince(t2);
    const FrameFlattening& f = a.entry->sheets.frames[k];
    auto stats =
        DeformReplyStatsOf(a.entry->id, f.quality, a.hit, format, imported, deformed.stats);
    stats->animation =
        DeformReplyStats::Frame{params.frame, params.animation->animation.frames, f.time};
    SURFDEFORM_ASSIGN_OR_RETURN(EncodeContext encode,
                                EncodeContextFor(deformed.mesh, params.output, format, work));
    encode.etag = std::move(etag);
    return MeshReply(deformed.mesh, params.output, format, imported, a.hit,
                     {{"parse", work.parse_ms()},
                      {"flatten", a.flatten_ms},
                      {"deform", deform_ms},
                      {"subdivide", a.subdivide_ms}},
                     std::move(stats), encode);
  }

  // An answer by its key (proto/answer_key.hpp): 304 when the request's
  // If-None-Match names its ETag (before any work), else kept, else made
  // by `make` (given the ETag) and kept. gzip is made with the answer, and
  // kept with it, when the answer compresses and the request takes it.
  Result<Reply> KeptOrMade(const DeformRequest& request, const std::string& key, bool compresses,
                           const std::function<Result<Reply>(std::string etag)>& make) {
    const std::string etag = proto::AnswerEtag(key);
    if (proto::IfNoneMatchNames(request.if_none_match, etag)) return NotModified(etag);
    const bool gzip = compresses && AcceptsGzip(request.accept_encoding);
    bool kept = false;
    auto answer = answers.GetOrMake(
        key,
        [&]() -> Result<Reply> {
          SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, make(etag));
          if (gzip) AddGzip(&reply);
          return reply;
        },
        &kept);
    // Kept by a request that did not take gzip: made for this one alone.
    if (answer.ok() && kept && gzip && answer->gzip_body.empty()) AddGzip(&*answer);
    return answer;
  }

  // POST /v1/animate's work once its answer is not kept: the model imported,
  // placed and refined for every frame, deformed through each, and encoded
  // as one GLB of morph targets.
  Result<Reply> AnimateModel(const proto::AnimateParams& params, std::string_view mesh,
                             RequestWork& work, std::string etag) {
    const ServiceLimits& limits = options.limits;
    SURFDEFORM_ASSIGN_OR_RETURN(auto imported, MeshOf(params, mesh, work));
    DeformOptions deform;
    deform.placement = PlacementFor(params.placement, imported, work.threads());
    deform.subdivision = WithRunDefaults<SubdivisionOptions>(params.subdivision);
    deform.geometry_only = true;
    // Checked before any work on the input's count, and again after the
    // subdivision on the output's.
    SURFDEFORM_RETURN_IF_ERROR(
        CheckFrameVertices(limits, static_cast<size_t>(params.animation.animation.frames),
                           imported.mesh.positions.size()));
    SURFDEFORM_ASSIGN_OR_RETURN(
        AnimatedModel a, PrepareAnimated(params.animation, std::move(imported.mesh), deform, work));
    const size_t frames = a.maps.size();
    SURFDEFORM_RETURN_IF_ERROR(CheckFrameVertices(limits, frames, a.model.mesh.positions.size()));

    const auto t2 = Clock::now();
    MorphAnimation anim;
    anim.base = &a.model.mesh;
    anim.fps = params.animation.animation.fps;
    anim.positions.resize(frames);
    if (a.model.need_frame && !a.model.mesh.normals.empty()) anim.normals.resize(frames);
    DeformStats first_stats;
    for (size_t k = 0; k < frames; ++k) {
      auto frame = DeformPrepared(a.maps[k], a.model, k, deform);
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
        for (size_t v = 0; v < m.normals.size(); ++v)
          anim.normals[k][v] = m.normals[v].cast<float>();
      }
      SURFDEFORM_RETURN_IF_ERROR(work.clock().Check("deformation"));
    }
    const double deform_ms = MsSince(t2);

    const auto t3 = Clock::now();
    AnimationGlbOptions glb;
    glb.compression = params.output.compression == proto::GlbCompression::kNone
                          ? AnimationCompression::kNone
                          : AnimationCompression::kMeshopt;
    glb.look.materials = imported.materials;
    glb.look.look = imported.look;
    glb.threads = work.threads();
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

    Reply reply = BytesReply(std::move(bytes), "model/gltf-binary", std::move(etag));
    reply.cache_hit = a.hit;
    reply.timings = {{"parse", work.parse_ms()},
                     {"flatten", a.flatten_ms},
                     {"subdivide", a.subdivide_ms},
                     {"deform", deform_ms},
                     {"encode", encode_ms}};
    auto stats = std::make_shared<AnimationReplyStats>();
    stats->animation_id = a.entry->id;
    stats->cached = a.hit;
    stats->frames = a.entry->sheets.frames;
    stats->fps = anim.fps;
    stats->vertices = a.model.mesh.positions.size();
    stats->triangles = a.model.mesh.triangles.size();
    stats->compression = NameOf<AnimationCompression>(kAnimationCompressions, glb.compression);
    stats->input_format = imported.format;
    stats->input_warnings = imported.warnings;
    stats->subdivision = a.model.subdivision;
    stats->subdivision_passes = a.model.subdivision_passes;
    stats->first_frame = first_stats;
    stats->text = imported.text_stats;
    SURFDEFORM_ASSIGN_OR_RETURN(reply.stats, CheckedStats(std::move(stats)));
    return reply;
  }

  const ServiceOptions options;
  SurfaceStore store;
  ModelStore models;
  FontStore fonts;
  Admission admission;
  ParseMemory parse_memory;  // the request JSON documents in flight
  // Placements and footprints of models that come back, by surface, options
  // and positions.
  PlacementMemo placements{kPlacementMemoEntries, options.limits.footprint_memo_bytes};
  AnswerCache answers{options.limits.answer_cache_bytes};
  MeshoptOrders orders;
};

Service::Service(ServiceOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
Service::~Service() = default;

const ServiceLimits& Service::limits() const { return impl_->options.limits; }
CacheStats Service::cache_stats() const { return impl_->store.surface_stats(); }
CacheStats Service::model_cache_stats() const { return impl_->models.stats(); }
CacheStats Service::answer_cache_stats() const { return impl_->answers.stats(); }
CacheStats Service::edit_paths_stats() const { return impl_->store.edit_paths_stats(); }
PlacementMemoStats Service::placement_memo_stats() const { return impl_->placements.stats(); }
AdmissionStats Service::admission_stats() const { return impl_->admission.stats(); }
bool Service::Saturated() const { return impl_->admission.Full(); }
int Service::RetryAfterSeconds() const { return impl_->admission.RetryAfterSeconds(); }
SharedTierStats Service::shared_tier_stats() const { return impl_->store.shared_tier_stats(); }
Retention Service::retention() const {
  return impl_->options.shared_tier != nullptr ? impl_->options.shared_tier->retention()
                                               : Retention{};
}
nlohmann::json Service::InfoJson() const {
  return surfdeform::InfoJson(impl_->options.limits, retention());
}

Result<Reply> Service::CreateSurface(std::string_view body, std::string_view field_side,
                                     const CancelFlag* cancel) {
  // No ticket up front: parsing is bounded by the JSON limits, and only a
  // flattening that this request must run itself is admitted.
  RequestWork work(impl_->options.limits, cancel, &impl_->parse_memory);
  SURFDEFORM_ASSIGN_OR_RETURN(int side, FieldSideOf(impl_->options.limits, field_side, "field", 0));
  SURFDEFORM_ASSIGN_OR_RETURN(auto parsed, work.ParseJson(body, "body"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto create, proto::ParseCreateSurfaceRequest(parsed));
  const proto::SurfaceRequest& request = create.request;
  SURFDEFORM_RETURN_IF_ERROR(work.EndParse());
  const RequestClock& clock = work.clock();
  const auto t1 = Clock::now();
  const WarmStart warm = WarmStartFor(create, impl_->store);
  const EditStart start{true, warm.entry.get()};
  bool hit = false;
  auto entry = impl_->store.Flattened(request, clock, &hit, &impl_->admission, start);
  if (!entry.ok() && entry.status().code() == ErrorCode::kUnavailable) {
    // The flattening this request waited on was refused (its caller found no
    // room): try once on this request's own account.
    entry = impl_->store.Flattened(request, clock, &hit, &impl_->admission, start);
  }
  if (!entry.ok()) return WithinBudget(clock, "flattening", entry.status());
  const double flatten_ms = MsSince(t1);
  json summary = SheetSummary(**entry, hit);
  summary["kept"] = RetentionJson(retention());
  if (!warm.from.empty()) summary["warm_start"] = WarmStartJson(warm, **entry, hit);
  SURFDEFORM_ASSIGN_OR_RETURN(std::string text, DumpFinite(summary, "reply"));
  double field_ms = 0.0;
  if (side != 0) {
    const auto t2 = Clock::now();
    SURFDEFORM_ASSIGN_OR_RETURN(SheetField field, impl_->FieldOf(**entry, side, work));
    SURFDEFORM_ASSIGN_OR_RETURN(std::string field_text, FieldJsonText(field, "field"));
    text = WithMember(std::move(text), "field", field_text);
    field_ms = MsSince(t2);
  }
  Reply reply = BytesReply(std::move(text), "application/json");
  reply.cache_hit = hit;
  reply.surface_id = (*entry)->id;
  reply.timings = {{"parse", work.parse_ms()}, {"flatten", flatten_ms}};
  if (side != 0) reply.timings.push_back({"field", field_ms});
  auto stats = std::make_shared<SurfaceReplyStats>();
  stats->surface_id = (*entry)->id;
  stats->cached = hit;
  reply.stats = std::move(stats);
  return reply;
}

Result<Reply> Service::GetSurface(std::string_view id) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto entry, impl_->store.Find(id));
  SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, JsonReply(SheetJson(*entry)));
  reply.cache_hit = true;
  return reply;
}

Result<Reply> Service::GetSurfaceField(std::string_view id, std::string_view side_text,
                                       std::string_view accept) {
  RequestWork work(impl_->options.limits);
  SURFDEFORM_ASSIGN_OR_RETURN(
      int side, FieldSideOf(impl_->options.limits, side_text, "n", kDefaultFieldSide));
  SURFDEFORM_ASSIGN_OR_RETURN(auto entry, impl_->store.Find(id));
  const auto t0 = Clock::now();
  SURFDEFORM_ASSIGN_OR_RETURN(SheetField field, impl_->FieldOf(*entry, side, work));
  Reply reply;
  if (PrefersBytesToJson(accept)) {
    reply = BytesReply(FieldBinary(field), "application/octet-stream");
  } else {
    SURFDEFORM_ASSIGN_OR_RETURN(std::string text, FieldJsonText(field));
    reply = BytesReply(std::move(text), "application/json");
  }
  reply.cache_hit = true;
  reply.surface_id = entry->id;
  reply.immutable = true;
  reply.timings = {{"field", MsSince(t0)}};
  return reply;
}

Result<Reply> Service::GetSurfaceSvg(std::string_view id) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto entry, impl_->store.Find(id));
  Reply reply = BytesReply(
      FlatSheetSvg(entry->sheet, "surfdeform flat sheet " + entry->id,
                   PeriodicInU(*entry->surface, entry->sheet),
                   PeriodicInV(*entry->surface, entry->sheet), entry->surface->flat_mesh()),
      "image/svg+xml");
  reply.cache_hit = true;
  return reply;
}

Result<Reply> Service::UploadModel(std::string_view mesh, std::string_view routed_id,
                                   const CancelFlag* cancel) {
  RequestWork work(impl_->options.limits, cancel, &impl_->parse_memory);
  if (mesh.empty()) return Status(ErrorCode::kMalformed, "the request carries no mesh", "mesh");
  const std::string id = proto::ModelId(mesh);
  if (!routed_id.empty() && routed_id != id) {
    return Status(ErrorCode::kMalformed,
                  "the X-Surfdeform-Model-Id header names model " + std::string(routed_id) +
                      " but the bytes' id is " + id +
                      " (the first 32 hex digits of their SHA-256): they must agree, since load "
                      "balancers route by the header",
                  "X-Surfdeform-Model-Id");
  }
  // Importing is work like any other: a slot first.
  SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
  bool known = false;
  SURFDEFORM_ASSIGN_OR_RETURN(auto model, impl_->models.Put(id, mesh, &known));
  SURFDEFORM_RETURN_IF_ERROR(work.EndParse());
  json summary = ModelSummary(*model);
  summary["kept"] = RetentionJson(retention());
  SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, JsonReply(summary));
  reply.cache_hit = known;
  reply.model_id = model->id;
  reply.timings = {{"parse", work.parse_ms()}};
  return reply;
}

Result<Reply> Service::UploadFont(std::string_view bytes, const CancelFlag* cancel) {
  RequestWork work(impl_->options.limits, cancel, &impl_->parse_memory);
  if (bytes.empty()) return Status(ErrorCode::kMalformed, "the request carries no font", "font");
  SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
  bool known = false;
  SURFDEFORM_ASSIGN_OR_RETURN(auto font, impl_->fonts.Put(bytes, &known));
  SURFDEFORM_RETURN_IF_ERROR(work.EndParse());
  json summary = FontJson(*font);
  summary["kept"] = RetentionJson(retention());
  SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, JsonReply(summary));
  reply.cache_hit = known;
  reply.model_id = font->id;
  reply.timings = {{"parse", work.parse_ms()}};
  return reply;
}

Result<Reply> Service::GetFont(std::string_view id) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto font, impl_->fonts.Find(id, "id"));
  json summary = FontJson(*font);
  summary["kept"] = RetentionJson(retention());
  return JsonReply(summary);
}

Result<Reply> Service::MakeText(std::string_view body, std::string_view accept,
                                const CancelFlag* cancel) {
  RequestWork work(impl_->options.limits, cancel, &impl_->parse_memory);
  SURFDEFORM_ASSIGN_OR_RETURN(auto parsed, work.ParseJson(body, "body"));
  SURFDEFORM_ASSIGN_OR_RETURN(proto::TextRequest request, proto::ParseTextRequest(parsed));
  std::optional<proto::OutputFormat> asked;
  if (request.format) {
    asked = ValueOf<proto::OutputFormat>(proto::kOutputFormats, *request.format);
    if (!asked) {
      return Status(ErrorCode::kInvalidArgument,
                    "must be one of " + OneOf<proto::OutputFormat>(proto::kOutputFormats) +
                        ", got \"" + *request.format + "\"",
                    "output.format");
    }
  }
  SURFDEFORM_ASSIGN_OR_RETURN(auto format, ChooseOutputFormat(asked, accept));
  SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
  SURFDEFORM_ASSIGN_OR_RETURN(auto font, impl_->fonts.Find(request.text.font, "text.font"));
  const auto t1 = Clock::now();
  SURFDEFORM_ASSIGN_OR_RETURN(
      ImportedMesh made, MakeTextMesh(request.text, *font, impl_->fonts, impl_->options.limits.font,
                                      work.clock().cancel()));
  const double text_ms = MsSince(t1);
  auto stats = std::make_shared<TextReplyStats>();
  stats->vertices = made.mesh.positions.size();
  stats->triangles = made.mesh.triangles.size();
  stats->format = format;
  stats->text = made.text_stats;
  proto::OutputOptions output;
  output.format = format;
  return MeshReply(made.mesh, output, format, made, false,
                   {{"parse", work.parse_ms()}, {"text", text_ms}}, std::move(stats));
}

Result<Reply> Service::MakePart(std::string_view body, std::string_view accept,
                                std::string_view report, const CancelFlag* cancel) {
  RequestWork work(impl_->options.limits, cancel, &impl_->parse_memory);
  SURFDEFORM_ASSIGN_OR_RETURN(auto parsed, work.ParseJson(body, "body"));
  SURFDEFORM_ASSIGN_OR_RETURN(proto::PartRequest request, proto::ParsePartRequest(parsed));
  SURFDEFORM_RETURN_IF_ERROR(work.EndParse());
  if (!report.empty() && report != "json") {
    return Status(ErrorCode::kInvalidArgument,
                  "must be \"json\" (the part's report instead of the part), got \"" +
                      std::string(report.substr(0, 32)) + "\"",
                  "report");
  }
  // No output.format and no Accept (or anything): 3MF, the printing format
  // that carries its unit.
  std::optional<proto::OutputFormat> asked = request.output.format;
  if (!asked && (accept.empty() || accept == "*/*")) asked = proto::OutputFormat::k3mf;
  SURFDEFORM_ASSIGN_OR_RETURN(auto format, ChooseOutputFormat(asked, accept));
  if (!request.body_model_id.empty()) {
    auto model = impl_->models.Find(request.body_model_id);
    if (!model.ok()) {
      return Status(model.status().code(), model.status().message(), "body.model_id");
    }
    const Mesh& uploaded = (*model)->imported.mesh;
    SURFDEFORM_RETURN_IF_ERROR(CheckUploadedPartSize(uploaded, impl_->options.limits));
    SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
    SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, MakeUploadedPartReply(request, uploaded, format,
                                                                   report == "json", work.clock()));
    reply.timings.insert(reply.timings.begin(), Timing{"parse", work.parse_ms()});
    return reply;
  }
  std::unique_ptr<Surface> inline_surface;
  std::shared_ptr<const StoredSurface> entry;
  const Surface* surface = nullptr;
  if (request.surface) {
    if (std::holds_alternative<MeshSpec>(*request.surface)) {
      return InvalidArgument(
          "a body is grown from a parametric surface; a surface given as a mesh has no "
          "parameters to thicken it by",
          "surface.kind");
    }
    auto made = MakeSurface(*request.surface);
    if (!made.ok()) return made.status().WithFieldPrefix("surface");
    inline_surface = std::move(*made);
    surface = inline_surface.get();
  } else {
    auto found = impl_->store.Find(request.surface_id);
    if (!found.ok()) return Status(found.status().code(), found.status().message(), "surface_id");
    entry = *found;
    surface = entry->surface.get();
  }
  SURFDEFORM_RETURN_IF_ERROR(CheckPartSize(request, *surface, impl_->options.limits));
  SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
  SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, MakePartReply(request, *surface, request.surface_id,
                                                         format, report == "json", work.clock()));
  reply.timings.insert(reply.timings.begin(), Timing{"parse", work.parse_ms()});
  return reply;
}

Result<Reply> Service::ListFonts() {
  json list = FontListJson(impl_->fonts);
  list["uploaded"] = {{"kept", RetentionJson(retention())},
                      {"limits", FontLimitsJson(impl_->options.limits.font)}};
  return JsonReply(list);
}

Result<Reply> Service::GetModel(std::string_view id) {
  auto found = impl_->models.Find(id);
  if (!found.ok()) return Status(found.status().code(), found.status().message(), "id");
  const std::shared_ptr<const StoredModel>& model = *found;
  json summary = ModelSummary(*model);
  summary["kept"] = RetentionJson(retention());
  SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, JsonReply(summary));
  reply.cache_hit = true;
  reply.model_id = model->id;
  return reply;
}

Result<Reply> Service::MapOnSurface(std::string_view id, std::string_view body,
                                    const CancelFlag* cancel) {
  const ServiceLimits& limits = impl_->options.limits;
  RequestWork work(limits, cancel, &impl_->parse_memory);
  SURFDEFORM_ASSIGN_OR_RETURN(auto parsed, work.ParseJson(body, "body"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto request, proto::ParseMapRequest(parsed, kMapLimits));
  SURFDEFORM_ASSIGN_OR_RETURN(auto entry, impl_->store.Find(id));
  SURFDEFORM_RETURN_IF_ERROR(work.EndParse());
  // Up to a million surface evaluations: a slot like any other work.
  SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
  const auto t1 = Clock::now();
  const SheetMap& map = *entry->map;
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
      auto o = WithRunDefaults<PolylineOptions>(request.polyline);
      o.max_points = MaxMapOutputPoints(limits);
      SURFDEFORM_ASSIGN_OR_RETURN(marks, ResamplePolylines(map, request.polylines, o));
      break;
    }
  }
  SURFDEFORM_ASSIGN_OR_RETURN(Reply reply, JsonReply(proto::MapResponseJson(request.kind, marks)));
  reply.cache_hit = true;
  reply.surface_id = entry->id;
  reply.timings = {{"parse", work.parse_ms()}, {"map", MsSince(t1)}};
  return reply;
}

Result<Reply> Service::Deform(const DeformRequest& request) {
  RequestWork work(impl_->options.limits, request.cancel, &impl_->parse_memory);
  SURFDEFORM_ASSIGN_OR_RETURN(auto parsed, work.ParseJson(request.params, "params"));
  RouteSurfaceId(request.routed_surface_id, &parsed);
  // Errors name their fields by JSON path in the parameters.
  SURFDEFORM_ASSIGN_OR_RETURN(auto params, proto::ParseDeformParams(parsed));
  SURFDEFORM_RETURN_IF_ERROR(CheckRoutedSurface(request.routed_surface_id, params));
  SURFDEFORM_ASSIGN_OR_RETURN(auto format,
                              ChooseOutputFormat(params.output.format, request.accept));
  SURFDEFORM_RETURN_IF_ERROR(CheckDistortionFormat(params.output, format));
  SURFDEFORM_RETURN_IF_ERROR(CheckOneMesh(params.model_id, request.mesh));
  SURFDEFORM_RETURN_IF_ERROR(CheckTextAlone(params.text, request.mesh));
  SURFDEFORM_RETURN_IF_ERROR(PlaceTextOnItsPath(params.text, &params.placement));
  SURFDEFORM_ASSIGN_OR_RETURN(const std::string model, impl_->ModelKeyOf(params, request.mesh));
  if (params.animation) {  // one frame, kept by the animation's content id and the frame
    const std::string frame = "animation/" + proto::AnimationId(*params.animation) + "/frame/" +
                              std::to_string(params.frame);
    return impl_->KeptOrMade(
        request,
        proto::AnswerKey({model, frame, &params.placement, &params.subdivision, &params.output,
                          format, impl_->options.limits.glb_split_vertices}),
        Compresses(params.output, format), [&](std::string etag) -> Result<Reply> {
          SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
          SURFDEFORM_ASSIGN_OR_RETURN(auto imported, impl_->MeshOf(params, request.mesh, work));
          return impl_->DeformFrame(params, std::move(imported), format, work, std::move(etag));
        });
  }

  // The sheet: held (by id), or flattened now with this request's slot.
  const auto t1 = Clock::now();
  bool hit = true;
  std::shared_ptr<const StoredSurface> entry;
  WarmStart warm;
  if (params.surface) {  // it may have to be flattened: a slot first
    SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
    if (!params.warm_start.empty()) {
      warm = WarmStartFor(*params.surface, params.warm_start, impl_->store);
    }
  }
  SURFDEFORM_ASSIGN_OR_RETURN(entry, impl_->SurfaceOf(params, warm, work.clock(), &hit));
  const double flatten_ms = MsSince(t1);
  // An edit: the placement was given on the sheet it started from.
  const std::optional<SheetMotion> motion = MotionOf(warm, *entry);
  if (motion) MovePlacement(*motion, &params.placement);

  // The answer's key, before any work on the model.
  const std::string sheet = entry->id + "/" + SheetDigest(entry->sheet);
  auto reply = impl_->KeptOrMade(
      request,
      proto::AnswerKey({model, sheet, &params.placement, &params.subdivision, &params.output,
                        format, impl_->options.limits.glb_split_vertices}),
      Compresses(params.output, format), [&](std::string etag) -> Result<Reply> {
        if (work.threads() == 0) {
          SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
        }
        SURFDEFORM_ASSIGN_OR_RETURN(auto imported, impl_->MeshOf(params, request.mesh, work));
        SURFDEFORM_RETURN_IF_ERROR(work.clock().Check("flattening"));
        return impl_->DeformOnSheet(params, *entry, hit, format, std::move(imported), work,
                                    flatten_ms, std::move(etag));
      });
  if (!reply.ok() || warm.from.empty()) return reply;
  // The edit's account, this request's own (a kept answer may have been
  // made from another start): the warm start, and where the placement went.
  const auto* made = dynamic_cast<const DeformReplyStats*>(reply->stats.get());
  if (made == nullptr) return reply;
  auto stats = std::make_shared<DeformReplyStats>(*made);  // the kept answer's stay as made
  stats->warm_start = WarmStartJson(warm, *entry, hit, motion);
  if (motion) {
    json& moved = stats->warm_start["placement"];
    moved["rotation_deg"] = params.placement.rotation_deg;
    if (params.placement.center_mode == CenterMode::kSheetUnits) {
      moved["center"] = {params.placement.center.x(), params.placement.center.y()};
    }
  }
  reply->stats = std::move(stats);
  return reply;
}

Result<Reply> Service::Animate(const DeformRequest& request) {
  const ServiceLimits& limits = impl_->options.limits;
  RequestWork work(limits, request.cancel, &impl_->parse_memory);
  SURFDEFORM_ASSIGN_OR_RETURN(auto parsed, work.ParseJson(request.params, "params"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto params, proto::ParseAnimateParams(parsed));
  SURFDEFORM_RETURN_IF_ERROR(CheckFrames(limits, params.animation));
  SURFDEFORM_RETURN_IF_ERROR(AcceptGlbOnly(request.accept));
  SURFDEFORM_RETURN_IF_ERROR(CheckOneMesh(params.model_id, request.mesh));
  SURFDEFORM_RETURN_IF_ERROR(CheckTextAlone(params.text, request.mesh));
  SURFDEFORM_RETURN_IF_ERROR(PlaceTextOnItsPath(params.text, &params.placement));
  // The answer's key and ETag, before any work: the model's id and the
  // animation's content id (its keys, frames, fps, sampling, flattening)
  // name every sheet; the placement, subdivision and compression the rest.
  SURFDEFORM_ASSIGN_OR_RETURN(const std::string model, impl_->ModelKeyOf(params, request.mesh));
  const std::string sheets = "animation/" + proto::AnimationId(params.animation);
  const std::string key = proto::AnswerKey({model, sheets, &params.placement, &params.subdivision,
                                            &params.output, proto::OutputFormat::kGlb, 0});
  return impl_->KeptOrMade(
      request, key, Compresses(params.output, proto::OutputFormat::kGlb),
      [&](std::string etag) -> Result<Reply> {
        SURFDEFORM_RETURN_IF_ERROR(work.Admit(impl_->admission, impl_->options.engine_threads));
        return impl_->AnimateModel(params, request.mesh, work, std::move(etag));
      });
}

}  // namespace surfdeform
