#include "proto/text_json.hpp"

namespace surfdeform::proto {
namespace {

using json = nlohmann::json;

Status ReadPath(const json& value, const std::string& path, TextPath* out) {
  SURFDEFORM_ASSIGN_OR_RETURN(JsonObject o, JsonObject::Open(value, path));
  const json* arc = o.Find("arc_mm");
  const json* points = o.Find("sheet_points");
  if ((arc != nullptr) == (points != nullptr)) {
    return Malformed(
        "give one of \"arc_mm\" (a circle's radius) and \"sheet_points\" (a "
        "polyline on the sheet)",
        path);
  }
  if (arc != nullptr) {
    out->kind = TextPathKind::kArc;
    SURFDEFORM_RETURN_IF_ERROR(o.Number("arc_mm", &out->arc_mm));
  } else {
    out->kind = TextPathKind::kSheetPoints;
    const std::string p = o.PathOf("sheet_points");
    if (!points->is_array()) return Malformed("must be an array of [x, y] points", p);
    if (points->size() > 65536) {
      return Status(ErrorCode::kInvalidArgument,
                    "must have at most 65536 points, got " + std::to_string(points->size()), p);
    }
    out->sheet_points.resize(points->size());
    for (size_t k = 0; k < points->size(); ++k) {
      SURFDEFORM_RETURN_IF_ERROR(ReadVec2((*points)[k], JoinPath(p, k), &out->sheet_points[k]));
    }
  }
  return o.Finish();
}

}  // namespace

Status ReadText(JsonObject& parent, std::optional<TextSettings>* out) {
  const json* v = parent.Find("text");
  if (v == nullptr) return Status::Ok();
  const std::string path = parent.PathOf("text");
  SURFDEFORM_ASSIGN_OR_RETURN(JsonObject o, JsonObject::Open(*v, path));
  TextSettings t;
  if (o.Find("string") == nullptr) return Malformed("is required", o.PathOf("string"));
  SURFDEFORM_RETURN_IF_ERROR(o.String("string", &t.string));
  SURFDEFORM_RETURN_IF_ERROR(o.String("font", &t.font));
  SURFDEFORM_RETURN_IF_ERROR(o.Number("size_mm", &t.size_mm));
  SURFDEFORM_RETURN_IF_ERROR(o.Number("depth_mm", &t.depth_mm));
  SURFDEFORM_RETURN_IF_ERROR(o.Number("letter_spacing_mm", &t.letter_spacing_mm));
  SURFDEFORM_RETURN_IF_ERROR(o.Number("line_spacing", &t.line_spacing));
  SURFDEFORM_RETURN_IF_ERROR(o.Choice<TextAlign>("align", kTextAligns, &t.align));
  SURFDEFORM_RETURN_IF_ERROR(o.Choice<TextDirection>("direction", kTextDirections, &t.direction));
  SURFDEFORM_RETURN_IF_ERROR(o.String("script", &t.script));
  SURFDEFORM_RETURN_IF_ERROR(o.String("language", &t.language));
  if (const json* f = o.Find("features"); f != nullptr) {
    const std::string p = o.PathOf("features");
    if (!f->is_array()) return Malformed("must be an array of strings (\"kern\", \"liga\")", p);
    if (f->size() > 64) {
      return Status(ErrorCode::kInvalidArgument,
                    "lists more than 64 features (" + std::to_string(f->size()) + ")", p);
    }
    t.features.clear();
    for (size_t k = 0; k < f->size(); ++k) {
      if (!(*f)[k].is_string()) return Malformed("must be a string", JoinPath(p, k));
      t.features.push_back((*f)[k].get<std::string>());
    }
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Number("tolerance_mm", &t.tolerance_mm));
  if (const json* p = o.Find("path"); p != nullptr) {
    SURFDEFORM_RETURN_IF_ERROR(ReadPath(*p, o.PathOf("path"), &t.path));
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  SURFDEFORM_RETURN_IF_ERROR(ValidateTextSettings(t, path));
  *out = std::move(t);
  return Status::Ok();
}

Result<TextRequest> ParseTextRequest(const json& body) {
  SURFDEFORM_ASSIGN_OR_RETURN(JsonObject o, JsonObject::Open(body, ""));
  std::optional<TextSettings> text;
  SURFDEFORM_RETURN_IF_ERROR(ReadText(o, &text));
  if (!text) return Malformed("is required", "text");
  TextRequest out{std::move(*text), std::nullopt};
  if (const json* v = o.Find("output"); v != nullptr) {
    SURFDEFORM_ASSIGN_OR_RETURN(JsonObject out_o, JsonObject::Open(*v, o.PathOf("output")));
    std::string format;
    if (out_o.Find("format") != nullptr) {
      SURFDEFORM_RETURN_IF_ERROR(out_o.String("format", &format));
      out.format = format;
    }
    SURFDEFORM_RETURN_IF_ERROR(out_o.Finish());
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return out;
}

json CanonicalJson(const TextSettings& t) {
  json j = {{"string", t.string},
            {"font", t.font},
            {"size_mm", t.size_mm},
            {"depth_mm", t.depth_mm},
            {"letter_spacing_mm", t.letter_spacing_mm},
            {"line_spacing", t.line_spacing},
            {"align", std::string(NameOf<TextAlign>(kTextAligns, t.align))},
            {"direction", std::string(NameOf<TextDirection>(kTextDirections, t.direction))},
            {"script", t.script},
            {"language", t.language},
            {"features", t.features},
            {"tolerance_mm", t.tolerance_mm}};
  if (t.path.kind == TextPathKind::kArc) j["path"] = {{"arc_mm", t.path.arc_mm}};
  if (t.path.kind == TextPathKind::kSheetPoints) {
    json pts = json::array();
    for (const Vec2& p : t.path.sheet_points) pts.push_back({p.x(), p.y()});
    j["path"] = {{"sheet_points", pts}};
  }
  return j;
}

}  // namespace surfdeform::proto
