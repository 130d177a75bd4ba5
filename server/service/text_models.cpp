#include "service/text_models.hpp"

#include <nlohmann/json.hpp>

#include "proto/content_hash.hpp"
#include "proto/text_json.hpp"
#include "text/text_model.hpp"
#include "text/text_shaping.hpp"

namespace surfdeform {
namespace {

using json = nlohmann::json;

}  // namespace

Status CheckTextAlone(const std::optional<TextSettings>& text, std::string_view body) {
  if (!text || body.empty()) return Status::Ok();
  return Status(ErrorCode::kMalformed,
                "the parameters give a \"text\" and the request carries a mesh too: a text is the "
                "whole model; send the parameters alone (a JSON body)",
                "text");
}

Status PlaceTextOnItsPath(const std::optional<TextSettings>& text, PlacementSettings* p) {
  if (!text || text->path.kind != TextPathKind::kSheetPoints) return Status::Ok();
  const char* given = nullptr;
  if (p->center_mode != CenterMode::kSheetCenter) given = "placement.center";
  if (p->rotation_deg != 0.0) given = "placement.rotation_deg";
  if (p->fit || p->scale != 1.0) given = "placement.scale";
  if (given != nullptr) {
    return Status(ErrorCode::kInvalidArgument,
                  "a text on text.path.sheet_points is set where its points are; leave the "
                  "placement's center, rotation_deg and scale out",
                  given);
  }
  p->center_mode = CenterMode::kSheetUnits;
  p->center = Vec2::Zero();
  return Status::Ok();
}

std::string TextModelKey(const TextSettings& text, const std::string& font_id) {
  return "text-" +
         proto::Sha256Hex(
             "surfdeform-text-1\n" + proto::CanonicalJson(text).dump() + "\n" + font_id, 32);
}

json FontJson(const StoredFont& f) {
  json j = {{"id", f.id},
            {"family", f.info.family},
            {"style", f.info.style},
            {"format", f.info.format},
            {"glyphs", f.info.glyphs},
            {"units_per_em", f.info.units_per_em},
            {"scripts", f.info.scripts},
            {"bytes", f.bytes->size()}};
  if (!f.name.empty()) j["name"] = f.name;
  return j;
}

json FontListJson(const FontStore& fonts) {
  json list = json::array();
  for (const auto& f : fonts.builtin()) list.push_back(FontJson(*f));
  json scripts = json::array();
  for (const ScriptProbe& p : ScriptProbes())
    scripts.push_back({{"script", p.script}, {"name", p.name}});
  // Built-in fonts whose files were not found (their packages are not installed).
  return {{"fonts", list},
          {"scripts", scripts},
          {"default", "DejaVuSans"},
          {"missing", fonts.missing()}};
}

Result<ImportedMesh> MakeTextMesh(const TextSettings& text, const StoredFont& font,
                                  const FontStore& fonts, const FontLimits& limits,
                                  const CancelFlag* cancel) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto face, FontFace::Open(*font.bytes, limits));
  if (auto cps = DecodeUtf8(text.string); cps.ok()) {
    const std::vector<char32_t> missing = MissingCodePoints(*face, *cps);
    if (!missing.empty()) {
      auto model = MakeTextModel(*face, text, cancel);  // its message lists them
      std::string message = model.ok() ? "" : model.status().message();
      const std::vector<std::string> with =
          fonts.BuiltinsWith(std::u32string(missing.begin(), missing.end()));
      message += with.empty() ? "; no built-in font has them all: upload one that does (POST "
                                "/v1/fonts)"
                              : "; built-in fonts that have them: " + [&] {
                                  std::string s;
                                  for (const auto& n : with) s += (s.empty() ? "" : ", ") + n;
                                  return s;
                                }();
      return Status(ErrorCode::kInvalidArgument, message, "text.string");
    }
  }
  SURFDEFORM_ASSIGN_OR_RETURN(TextModel model, MakeTextModel(*face, text, cancel));
  ImportedMesh out;
  out.format = MeshFormat::kUnknown;
  out.centre_at_origin = true;
  for (const MeshGroup& g : model.mesh.groups) out.materials.push_back(g.name);
  for (size_t k = 0; k < model.mesh.groups.size(); ++k) {
    model.mesh.groups[k].material = static_cast<int>(k);
  }
  auto stats = std::make_shared<TextStats>();
  stats->font = font.name.empty() ? font.id : font.name;
  stats->family = font.info.family;
  stats->style = font.info.style;
  stats->glyphs = model.glyphs.size();
  stats->solids = model.mesh.groups.size();
  stats->lines = model.lines;
  stats->width_mm = model.width_mm;
  stats->outline_points = model.outline_points;
  stats->area_mm2 = model.area_mm2;
  stats->runs = model.runs;
  for (const TextGlyph& g : model.glyphs) {
    if (stats->clusters.size() >= TextStats::kMaxClusters) break;
    stats->clusters.push_back({g.cluster, g.glyph, g.line, g.s_mm, g.advance_mm});
  }
  stats->path_length_mm = model.path_length_mm;
  out.text_stats = std::move(stats);
  out.mesh = std::move(model.mesh);
  return out;
}

json TextStats::ToJson() const {
  json each = json::array();
  for (const Cluster& c : clusters) {
    each.push_back({{"text", c.text},
                    {"glyph", c.glyph},
                    {"line", c.line},
                    {"s_mm", c.s_mm},
                    {"advance_mm", c.advance_mm}});
  }
  json j = {{"font", font},
            {"family", family},
            {"style", style},
            {"glyphs", glyphs},
            {"solids", solids},
            {"lines", lines},
            {"width_mm", width_mm},
            {"outline_points", outline_points},
            {"area_mm2", area_mm2},
            {"runs", runs},
            {"clusters", std::move(each)}};
  if (path_length_mm > 0) j["path_length_mm"] = path_length_mm;
  return j;
}

}  // namespace surfdeform
