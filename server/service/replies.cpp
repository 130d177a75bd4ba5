#include "service/replies.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "base/format.hpp"
#include "engine/common/elapsed.hpp"
#include "engine/flatten/flatten.hpp"
#include "engine/flatten/mesh_flatten.hpp"
#include "engine/flatten/seam_extension.hpp"
#include "engine/placement/placement.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/subdivision/subdivide.hpp"
#include "meshio/mesh_export.hpp"
#include "proto/content_hash.hpp"
#include "proto/surface_json.hpp"
#include "service/limit_checks.hpp"
#include "service/output_negotiation.hpp"
#include "service/reply_stats.hpp"
#include "service/stats_json.hpp"
#include "service/text_models.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// The stats' per-item lists, which BoundedStats may cut: "each" (a rigid
// model's parts, an animation's frames) and a text's "clusters".
constexpr std::string_view kPerItemLists[] = {"each", "clusters"};

// A per-item list: the object that holds it, and its key there.
struct ListAt {
  json* owner;
  std::string key;
  json& list() const { return (*owner)[key]; }
};

// The per-item lists under `j`; not those inside such a list, whose items
// the cut erases (a pointer to one would dangle).
void CollectLists(json& j, std::vector<ListAt>* lists) {
  if (j.is_object()) {
    for (auto& [key, value] : j.items()) {
      const bool per_item = std::find(std::begin(kPerItemLists), std::end(kPerItemLists), key) !=
                            std::end(kPerItemLists);
      if (per_item && value.is_array()) {
        lists->push_back({&j, key});
      } else {
        CollectLists(value, lists);
      }
    }
  } else if (j.is_array()) {
    for (json& item : j) CollectLists(item, lists);
  }
}

}  // namespace

std::string Dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

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

Status NonFiniteNumber(std::string_view what, const std::string& at) {
  return Status(ErrorCode::kInvalidArgument,
                "the " + std::string(what) + "'s " + at +
                    " would not be a finite number: the request's coordinates or sizes are "
                    "too large to compute with in double precision",
                at);
}

Result<std::string> DumpFinite(const json& j, std::string_view what) {
  const std::string at = FirstNonFiniteNumber(j, "");
  if (at.empty()) return Dump(j);
  return NonFiniteNumber(what, at);
}

Result<json> BoundedStats(json stats) {
  SURFDEFORM_ASSIGN_OR_RETURN(std::string text, DumpFinite(stats, "statistics"));
  std::vector<ListAt> lists;
  CollectLists(stats, &lists);
  while (text.size() > kMaxStatsHeaderBytes) {
    const ListAt* longest = nullptr;
    for (const ListAt& l : lists) {
      if (longest == nullptr || l.list().size() > longest->list().size()) longest = &l;
    }
    if (longest == nullptr || longest->list().empty()) break;
    json& list = longest->list();
    const size_t cut = (list.size() + 1) / 2;
    list.erase(list.end() - static_cast<long>(cut), list.end());
    const std::string omitted = longest->key + "_omitted";
    (*longest->owner)[omitted] = longest->owner->value(omitted, size_t{0}) + cut;
    text = StatsJsonText(stats);
  }
  return stats;
}

Reply BytesReply(std::string body, std::string content_type, std::string etag) {
  Reply reply;
  reply.body = std::move(body);
  reply.content_type = std::move(content_type);
  reply.etag = etag.empty() ? proto::Sha256Hex(reply.body, 32) : std::move(etag);
  return reply;
}

Result<std::shared_ptr<const ReplyStats>> CheckedStats(std::shared_ptr<const ReplyStats> stats) {
  if (stats) {
    const std::string at = FirstNonFiniteNumber(stats->ToJson(), "");
    if (!at.empty()) return NonFiniteNumber("statistics", at);
  }
  return stats;
}

std::string StatsHeaderText(const Reply& reply) {
  if (!reply.stats) return "";
  json stats = reply.stats->ToJson();
  if (reply.answer_kept) {
    stats["answer_kept"] = true;
    stats["cached"] = true;  // nothing was flattened for it
  }
  auto bounded = BoundedStats(std::move(stats));
  return bounded.ok() ? StatsJsonText(*bounded) : "";
}

void MarkKept(Reply* reply) {
  reply->cache_hit = true;
  reply->timings.clear();
  reply->answer_kept = true;
}

Reply NotModified(std::string etag) {
  Reply reply;
  reply.etag = std::move(etag);
  reply.not_modified = true;
  return reply;
}

Result<Reply> JsonReply(const json& body) {
  SURFDEFORM_ASSIGN_OR_RETURN(std::string text, DumpFinite(body, "reply"));
  return BytesReply(std::move(text), "application/json");
}

json SheetSummary(const StoredSurface& s, bool cached) {
  json j = {{"id", s.id},
            {"cached", cached},
            {"grid", {{"nu", s.sheet.nu}, {"nv", s.sheet.nv}}},
            {"method", s.sheet.method},
            {"periodic_u", false},
            {"periodic_v", false},
            {"quality", QualityJson(s.sheet.quality)},
            {"timing_ms", {{"flatten", s.flatten_ms}}}};
  if (const std::optional<SheetPeriod> period = PeriodOf(*s.surface, s.sheet)) {
    // A model may cross the seam: the flat point p of the column u = 0 and
    // R(angle) p + translation of the column u = 1 are one surface point.
    j["periodic_u"] = true;
    j["period"] = {{"angle_deg", period->angle * 180.0 / std::numbers::pi},
                   {"translation", {period->translation.x(), period->translation.y()}}};
  }
  if (PeriodicInV(*s.surface, s.sheet)) {
    // The same in v (a whole torus, a tube): the row v = 0 moved by the
    // translation is the row v = 1.
    j["periodic_v"] = true;
    j["period_v"] = {{"translation", {s.sheet.period_v.x(), s.sheet.period_v.y()}}};
  }
  if (const FlatMesh* m = s.surface->flat_mesh()) {
    // A surface given as a mesh: what was flattened.
    j["mesh"] = {{"vertices", m->flat.size()},
                 {"triangles", m->mesh.triangles.size()},
                 {"boundary_vertices", m->mesh.boundary.size()},
                 {"welded", m->mesh.welded},
                 {"unused_vertices", m->mesh.dropped},
                 {"pairs", m->pairs},
                 {"pairs_off_the_mesh", m->dropped_pairs}};
  }
  return j;
}

json SheetJson(const StoredSurface& s) {
  json j = SheetSummary(s, true);
  j["request"] = proto::CanonicalJson(s.request);
  json flat = json::array();
  for (const Vec2& p : s.sheet.flat) flat.push_back({p.x(), p.y()});
  j["points"] = proto::PointsJson(s.sheet.points);
  j["flat"] = std::move(flat);
  if (const FlatMesh* m = s.surface->flat_mesh()) {
    // The flat triangles in the sheet's frame: the sheet itself, where the
    // grid above only samples its box.
    json vertices = json::array();
    json triangles = json::array();
    for (const Vec2& p : m->flat) {
      const Vec2 q = s.sheet.frame_linear * p + s.sheet.frame_offset;
      vertices.push_back({q.x(), q.y()});
    }
    for (const auto& t : m->mesh.triangles) triangles.push_back({t[0], t[1], t[2]});
    j["mesh"]["flat"] = std::move(vertices);
    j["mesh"]["points"] = proto::PointsJson(m->mesh.positions);  // in space (welded)
    j["mesh"]["triangles"] = std::move(triangles);
  }
  return j;
}

GlbEncoding GlbEncodingOf(const proto::OutputOptions& output, proto::OutputFormat format) {
  if (format == proto::OutputFormat::kGlbPlain) return GlbEncoding::kPlain;
  switch (output.compression.value_or(proto::GlbCompression::kDraco)) {
    case proto::GlbCompression::kMeshopt:
      return GlbEncoding::kMeshopt;
    case proto::GlbCompression::kNone:
      return GlbEncoding::kQuantized;
    case proto::GlbCompression::kDraco:
      break;
  }
  return GlbEncoding::kDraco;
}

Result<Reply> MeshReply(const Mesh& mesh, const proto::OutputOptions& output,
                        proto::OutputFormat format, const ImportedMesh& imported, bool hit,
                        std::vector<Timing> timings, std::shared_ptr<EncodedMeshStats> stats,
                        const EncodeContext& encode) {
  const auto t0 = Clock::now();
  ExportOptions export_options;
  export_options.draco = output.draco;
  export_options.glb = GlbEncodingOf(output, format);
  export_options.materials = imported.materials;
  export_options.look = imported.look;
  export_options.meshopt_order = encode.meshopt_order;
  export_options.threads = std::max(1, encode.threads);
  export_options.split_vertices = encode.glb_split_vertices;
  export_options.object_name = encode.object_name;
  SURFDEFORM_ASSIGN_OR_RETURN(auto bytes,
                              ExportMesh(mesh, OutputMeshFormat(format), export_options));
  timings.push_back({"encode", MsSince(t0)});
  Reply reply = BytesReply(std::move(bytes), proto::OutputMediaType(format), encode.etag);
  reply.cache_hit = hit;
  reply.timings = std::move(timings);
  if (stats && format == proto::OutputFormat::kGlb) {
    stats->compression = NameOf<proto::GlbCompression>(
        proto::kGlbCompressions, output.compression.value_or(proto::GlbCompression::kDraco));
    if (export_options.glb == GlbEncoding::kDraco) {
      stats->pieces = GlbPieces(mesh.positions.size(), encode.glb_split_vertices);
    }
  }
  SURFDEFORM_ASSIGN_OR_RETURN(reply.stats, CheckedStats(std::move(stats)));
  return reply;
}

json RetentionJson(const Retention& r) {
  json j = {{"where", r.where}, {"survives_restart", r.survives_restart}};
  j["ttl_s"] = r.ttl_s > 0 ? json(r.ttl_s) : json(nullptr);
  if (r.budget_bytes > 0) j["budget_bytes"] = r.budget_bytes;
  const std::string where = r.where;
  j["description"] =
      where == "disk"
          ? "kept in this server's data directory across restarts, until its byte budget "
            "evicts the least recently used"
      : where == "redis"
          ? "kept in Redis for ttl_s seconds (unless its maxmemory evicts it first), shared by "
            "replicas; across Redis restarts only with its persistence on (appendonly yes)"
          : "kept in this process's memory only, until its byte budget evicts the least "
            "recently used: lost when the server restarts";
  return j;
}

json ModelSummary(const StoredModel& m) {
  const ImportedMesh& in = m.imported;
  const Mesh& mesh = in.mesh;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  if (!mesh.positions.empty()) {
    lo = hi = mesh.positions[0];
    for (const Vec3& p : mesh.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  const char* reason = "default";
  const bool y_up = in.format == MeshFormat::kGlb || in.format == MeshFormat::kGltf;
  const UpAxis up = ResolveUpAxis(UpAxis::kAuto, y_up, mesh.positions, &reason);
  return {{"id", m.id},
          {"format", MeshFormatName(in.format)},
          {"file_bytes", m.file_bytes},
          {"vertices", mesh.positions.size()},
          {"triangles", mesh.triangles.size()},
          {"groups", std::max<size_t>(1, mesh.groups.size())},
          {"bounds", {{lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}}},
          {"up", NameOf<UpAxis>(kUpAxes, up)},
          {"up_reason", reason},
          {"warnings", in.warnings}};
}

json FontLimitsJson(const FontLimits& f) {
  return {{"max_font_bytes", f.max_font_bytes},
          {"max_font_memory", f.max_font_memory},
          {"max_glyphs", f.max_glyphs},
          {"max_glyph_points", f.max_glyph_points},
          {"max_text_code_points", f.max_text_code_points},
          {"max_text_cost", f.max_text_cost}};
}

json InfoJson(const ServiceLimits& l, const Retention& kept) {
  json j = {{"name", "surfdeform"},
            {"version", SURFDEFORM_VERSION},
            {"limits",
             {{"max_body_bytes", l.max_body_bytes},
              {"max_vertices", l.max_vertices},
              {"max_triangles", l.max_triangles},
              {"max_grid_side", l.max_grid_side},
              {"max_surface_mesh_vertices", l.max_surface_mesh_vertices},
              {"max_surface_mesh_pairs", l.max_surface_mesh_pairs},
              {"max_output_vertices", MaxOutputVertices(l)},
              {"max_output_triangles", l.max_output_triangles},
              {"max_subdivision_crossings", MaxSubdivisionCrossings(l)},
              {"max_json_depth", l.max_json_depth},
              {"max_json_elements", l.max_json_elements},
              {"max_json_elements_in_flight", l.max_json_elements_in_flight},
              {"max_json_string_bytes", l.max_json_string_bytes},
              {"max_in_flight", l.max_in_flight},
              {"max_queued", l.max_queued},
              {"queue_timeout_ms", l.queue_timeout_ms},
              {"flatten_time_budget_ms", l.flatten_time_budget_ms},
              {"request_time_budget_ms", l.request_time_budget_ms},
              {"max_field_side", l.max_field_side},
              {"cache_bytes", l.cache_bytes},
              {"model_cache_bytes", l.model_cache_bytes},
              {"answer_cache_bytes", l.answer_cache_bytes},
              {"glb_split_vertices", l.glb_split_vertices},
              {"max_map_points", kMapLimits.max_points},
              {"max_map_surface_points", kMapLimits.max_surface_points},
              {"max_map_output_points", MaxMapOutputPoints(l)},
              {"max_animation_frames", l.max_animation_frames},
              {"max_animation_frame_vertices", l.max_animation_frame_vertices},
              {"max_animation_bytes", l.max_animation_bytes},
              {"request_memory_bytes", l.request_memory_bytes}}},
            {"font_limits", FontLimitsJson(l.font)},
            {"uploads_kept", RetentionJson(kept)},
            {"input_formats", {"glb", "gltf", "drc", "obj", "ply", "stl", "off"}},
            {"output_formats", NamesOf<proto::OutputFormat>(proto::kOutputFormats)},
            {"surface_kinds", NamesOf<proto::SurfaceKind>(proto::kSurfaceKinds)},
            {"closed_surfaces",
             {{"periodic_u", {"cylinder", "cone", "sphere", "torus", "bspline", "nurbs", "grid"}},
              {"periodic_v", {"torus", "bspline", "nurbs", "grid"}},
              {"description",
               "a surface whose u closes is periodic in u: a cylinder or cone with angle_deg "
               "360, a sphere with 360 degrees of longitude, a torus with 360 degrees in u, a "
               "bspline, nurbs or grid with periodic_u (its seam must meet, to 1e-9 of its "
               "size, or it is refused with the gap). A "
               "model may lie across its seam and wrap round it (the sheet's periodic_u and "
               "period say so; the stats' placement.turns says how far round, and warn past "
               "one turn). Cylinders and cones are unrolled in closed form (their period is a "
               "translation or a rotation about the apex); the others are flattened with the "
               "pairs across the seam in the stress, into a strip whose period (a translation) "
               "is solved with the sheet. That needs at least 2 max(range, 3) + 2 samples in "
               "u and method majorization; otherwise the sheet keeps a seam no model may "
               "cross. The same holds in v for a torus with 360 degrees in v and a bspline, "
               "nurbs or grid with periodic_v (the sheet's periodic_v and period_v); a "
               "surface closed both ways (a whole torus) flattens to a flat torus"}}},
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
  publish("output.compression", proto::kGlbCompressions);
  publish("body.side", kBodySides);
  for (const auto& e : kErrorCodes) {  // problem+json's "code"
    if (e.value != ErrorCode::kOk)
      enums["problem.code"].push_back({{"name", e.name}, {"description", e.description}});
  }
  return j;
}

}  // namespace surfdeform
