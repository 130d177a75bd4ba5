#include "proto/answer_key.hpp"

#include "base/header_lists.hpp"
#include "proto/content_hash.hpp"

namespace surfdeform::proto {
namespace {

using nlohmann::json;

// Bumped whenever an answer's bytes change for the same key: an encoder's
// layout, the engine's arithmetic, the libraries' versions.
constexpr const char* kAnswerVersion = "surfdeform-answer-2";

template <typename E, size_t N>
std::string Name(const EnumEntry<E> (&table)[N], E value) {
  return std::string(NameOf<E>(table, value));
}

}  // namespace

json CanonicalJson(const PlacementOptions& p) {
  json anchor =
      p.anchor == AnchorMode::kValue ? json(p.anchor_value) : json(Name(kAnchorModes, p.anchor));
  json center;
  switch (p.center_mode) {
    case CenterMode::kSheetCenter:
      center = "center";
      break;
    case CenterMode::kSheetUnits:
      center = {p.center.x(), p.center.y()};
      break;
    case CenterMode::kFraction:
      center = {{"fraction", {p.center.x(), p.center.y()}}};
      break;
  }
  json j = {{"up", Name(kUpAxes, p.up)},      {"rigid", Name(kRigidModes, p.rigid)},
            {"anchor", std::move(anchor)},    {"center", std::move(center)},
            {"rotation_deg", p.rotation_deg}, {"outside", Name(kOutsideModes, p.outside)}};
  if (p.fit) {
    j["scale"] = "fit";
    j["fit_margin"] = p.fit_margin;
  } else {
    j["scale"] = p.scale;
  }
  return j;
}

json CanonicalJson(const SubdivisionOptions& s) {
  return {{"mode", Name(kSubdivisionModes, s.mode)},
          {"epsilon", s.epsilon},
          {"tolerance", s.tolerance}};
}

json CanonicalJson(const OutputOptions& o, OutputFormat format) {
  json j = {{"format", OutputFormatName(format)}, {"distortion", o.distortion}};
  bool draco = format == OutputFormat::kDrc;
  if (format == OutputFormat::kGlb) {
    const GlbCompression c = o.compression.value_or(GlbCompression::kDraco);
    j["compression"] = Name(kGlbCompressions, c);
    draco = c == GlbCompression::kDraco;
  }
  if (draco) {
    const DracoOptions& d = o.draco;
    j["draco"] = {{"position_bits", d.position_bits},
                  {"normal_bits", d.normal_bits},
                  {"uv_bits", d.uv_bits},
                  {"color_bits", d.color_bits},
                  {"speed", d.speed},
                  {"sequential", d.sequential}};
  }
  return j;
}

std::string AnswerKey(const AnswerKeyParts& parts) {
  const json j = {{"version", kAnswerVersion},
                  {"model", parts.model},
                  {"surface", parts.surface},
                  {"placement", CanonicalJson(*parts.placement)},
                  {"subdivision", CanonicalJson(*parts.subdivision)},
                  {"output", CanonicalJson(*parts.output, parts.format)},
                  {"glb_split_vertices", parts.glb_split_vertices}};
  return j.dump();  // nlohmann's objects keep their keys sorted
}

std::string AnswerEtag(std::string_view key) { return Sha256Hex(key, 32); }

bool IfNoneMatchNames(std::string_view header, std::string_view etag) {
  if (etag.empty()) return false;
  // An entity tag holds no ';' or ',' that this server writes, so the list
  // reader's elements are whole tags.
  return AnyHeaderListItem(header, [etag](const HeaderListItem& item) {
    std::string_view tag = item.value;
    if (tag.substr(0, 2) == "W/") tag.remove_prefix(2);  // the weak comparison
    if (tag.size() < etag.size() + 2 || tag.front() != '"' || tag.back() != '"') return false;
    const std::string_view inner = tag.substr(1, tag.size() - 2);
    // The gzipped representation's tag is the identity's with "-gzip".
    return inner == etag ||
           (inner.substr(0, etag.size()) == etag && inner.substr(etag.size()) == "-gzip");
  });
}

}  // namespace surfdeform::proto
