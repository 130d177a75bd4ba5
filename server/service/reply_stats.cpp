#include "service/reply_stats.hpp"

#include <algorithm>

#include "base/format.hpp"
#include "engine/placement/placement.hpp"
#include "service/stats_json.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;

// The input's warnings, and the placement's: a model longer than the
// circumference of a closed surface lies over itself.
json Warnings(const std::vector<std::string>& input, const DeformStats& st) {
  json warnings = input;
  if (st.turns > 1.0) {
    warnings.push_back(
        Format("the model goes %.3g times round the closed surface: it is longer "
               "than the circumference and lies over itself; scale it down "
               "(placement.scale) to stay within one turn",
               st.turns));
  }
  return warnings;
}

}  // namespace

json SurfaceReplyStats::ToJson() const { return {{"surface_id", surface_id}, {"cached", cached}}; }

void EncodedMeshStats::AddEncoding(json* j) const {
  if (compression) (*j)["compression"] = *compression;
  if (pieces > 1) (*j)["pieces"] = pieces;
}

json DeformReplyStats::ToJson() const {
  const DeformStats& st = deform;
  json j = {{"surface_id", surface_id},
            {"cached", cached},
            {"format", proto::OutputFormatName(format)},
            {"input_format", MeshFormatName(input_format)},
            {"vertices", st.vertices},
            {"triangles", st.triangles},
            {"subdivision", SubdivisionStatsJson(st.subdivision)},
            {"placement", DeformStatsJson(st)},
            {"quality", QualityJson(quality)},
            {"warnings", Warnings(input_warnings, st)}};
  if (text) j["text"] = text->ToJson();
  j["placement"]["reused"] = placement_reused;
  j["subdivision"]["reused"] = subdivision_reused;
  if (st.rigid.mode != RigidMode::kNone) {
    json each = json::array();
    for (size_t k = 0; k < st.rigid.each.size() && k < kMaxRigidParts; ++k) {
      const RigidPartStats& e = st.rigid.each[k];
      each.push_back({{"vertices", e.vertices}, {"lift", e.lift}, {"sink", e.sink}});
    }
    j["rigid"] = {{"mode", NameOf<RigidMode>(kRigidModes, st.rigid.mode)},
                  {"parts", st.rigid.parts},
                  {"max_lift", st.rigid.max_lift},
                  {"max_sink", st.rigid.max_sink},
                  {"each", std::move(each)}};  // BoundedStats cuts more
  }
  if (st.distortion.computed) {
    j["distortion"] = {
        {"max", st.distortion.max}, {"p95", st.distortion.p95}, {"mean", st.distortion.mean}};
  }
  if (animation) {
    j["animation"] = {
        {"frame", animation->frame}, {"frames", animation->frames}, {"time", animation->time}};
  }
  if (!warm_start.is_null()) j["warm_start"] = warm_start;
  AddEncoding(&j);
  return j;
}

std::shared_ptr<DeformReplyStats> DeformReplyStatsOf(const std::string& surface_id,
                                                     const FlattenQuality& quality, bool hit,
                                                     proto::OutputFormat format,
                                                     const ImportedMesh& imported,
                                                     const DeformStats& deform) {
  auto s = std::make_shared<DeformReplyStats>();
  s->surface_id = surface_id;
  s->quality = quality;
  s->cached = hit;
  s->format = format;
  s->input_format = imported.format;
  s->input_warnings = imported.warnings;
  s->text = imported.text_stats;
  s->deform = deform;
  // Only the parts the header can list are kept with the answer.
  auto& each = s->deform.rigid.each;
  if (each.size() > DeformReplyStats::kMaxRigidParts) each.resize(DeformReplyStats::kMaxRigidParts);
  return s;
}

json AnimationReplyStats::ToJson() const {
  const size_t n = frames.size();
  json per_frame = json::array();
  long long warm_iterations = 0;
  for (const FrameFlattening& f : frames) {
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
  const long long cold = n > 0 ? frames.front().quality.iterations : 0;
  json j = {{"animation_id", animation_id},
            {"cached", cached},
            {"frames", n},
            {"fps", fps},
            {"vertices", vertices},
            {"triangles", triangles},
            {"compression", compression},
            {"input_format", MeshFormatName(input_format)},
            {"subdivision", SubdivisionStatsJson(subdivision)},
            {"subdivision_passes", subdivision_passes},
            {"placement", DeformStatsJson(first_frame)},
            {"flatten",
             {{"iterations_first", cold},
              {"iterations_warm_mean",
               n > 1 ? static_cast<double>(warm_iterations) / static_cast<double>(n - 1) : 0.0},
              {"iterations_saved_estimate",
               std::max(0LL, cold * static_cast<long long>(n > 0 ? n - 1 : 0) - warm_iterations)},
              {"each", std::move(per_frame)}}},
            {"warnings", Warnings(input_warnings, first_frame)}};
  if (text) j["text"] = text->ToJson();
  return j;
}

json TextReplyStats::ToJson() const {
  json j = {{"vertices", vertices},
            {"triangles", triangles},
            {"format", proto::OutputFormatName(format)}};
  if (text) j["text"] = text->ToJson();
  AddEncoding(&j);
  return j;
}

json PartReplyStats::ToJson() const {
  const SolidReport& r = solid;
  const Vec3 size = r.hi - r.lo;
  json j = {{"format", proto::OutputFormatName(format)},
            {"units", "mm"},
            {"vertices", r.vertices},
            {"triangles", r.triangles},
            {"volume_mm3", r.volume},
            {"area_mm2", r.area},
            {"bounding_box_mm",
             {{"min", {r.lo.x(), r.lo.y(), r.lo.z()}},
              {"max", {r.hi.x(), r.hi.y(), r.hi.z()}},
              {"size", {size.x(), size.y(), size.z()}}}},
            {"body", model_id.empty() ? json{{"thickness_mm", part.thickness_mm},
                                             {"side", NameOf<BodySide>(kBodySides, part.side)},
                                             {"samples", {{"nu", nu}, {"nv", nv}}}}
                                      : json{{"model_id", model_id}}},
            {"checks",
             {{"closed", r.closed()},
              {"border_edges", r.border_edges},
              {"non_manifold_edges", r.non_manifold_edges},
              {"oriented", r.oriented()},
              {"degenerate_triangles", r.degenerate_triangles},
              {"self_intersections", r.self_intersects},
              {"volume_positive", r.volume > 0}}},
            {"thinnest_wall_mm", thinnest_wall_mm ? json(*thinnest_wall_mm) : json(nullptr)},
            {"printer", {{"min_wall_mm", part.min_wall_mm}, {"min_detail_mm", part.min_detail_mm}}},
            {"warnings", warnings}};
  if (!surface_id.empty()) j["surface_id"] = surface_id;
  AddEncoding(&j);
  return j;
}

}  // namespace surfdeform
