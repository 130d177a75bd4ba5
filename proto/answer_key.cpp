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

json CanonicalJson(const OutputOptions& o, OutputFormat format) {
  json j = {{"format", OutputFormatName(format)}, {"distortion", o.distortion}};
  bool draco = format == OutputFormat::kDrc;
  if (format == OutputFormat::kGlb) {
    const GlbCompression c = o.compression.value_or(GlbCompression::kDraco);
    j["compression"] = Name(kGlbCompressions, c);
    draco = c == GlbCompression::kDraco;
  }
  if (draco) j["draco"] = CanonicalJson(o.draco);
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
