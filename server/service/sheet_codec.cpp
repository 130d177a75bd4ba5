#include "service/sheet_codec.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>

#include "proto/api.hpp"
#include "proto/content_hash.hpp"
#include "service/stats_json.hpp"

namespace surfdeform {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the sheet format stores little-endian numbers as they are in memory");

constexpr char kMagic[4] = {'S', 'D', 'F', 'S'};
constexpr size_t kChecksumDigits = 32;  // hex digits of SHA-256

using nlohmann::json;

class Writer {
 public:
  void Bytes(const void* p, size_t n) { out_.append(static_cast<const char*>(p), n); }
  void U32(uint32_t v) { Bytes(&v, sizeof v); }
  void Text(const std::string& s) {
    U32(static_cast<uint32_t>(s.size()));
    out_ += s;
  }
  template <class V>
  void Vectors(const std::vector<V>& vs) {
    for (const V& v : vs) Bytes(v.data(), sizeof(double) * V::RowsAtCompileTime);
  }
  std::string Finish() {
    out_ += proto::Sha256Hex(out_, kChecksumDigits);
    return std::move(out_);
  }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}
  bool Bytes(void* p, size_t n) {
    if (in_.size() - pos_ < n) return false;
    std::memcpy(p, in_.data() + pos_, n);
    pos_ += n;
    return true;
  }
  bool U32(uint32_t* v) { return Bytes(v, sizeof *v); }
  bool Text(std::string* s, size_t max) {
    uint32_t n = 0;
    if (!U32(&n) || n > max || in_.size() - pos_ < n) return false;
    s->assign(in_.data() + pos_, n);
    pos_ += n;
    return true;
  }
  template <class V>
  bool Vectors(size_t count, std::vector<V>* vs) {
    constexpr size_t kSize = sizeof(double) * V::RowsAtCompileTime;
    if ((in_.size() - pos_) / kSize < count) return false;
    vs->resize(count);
    for (V& v : *vs) {
      Bytes(v.data(), kSize);
      if (!v.allFinite()) return false;
    }
    return true;
  }
  size_t left() const { return in_.size() - pos_; }

 private:
  std::string_view in_;
  size_t pos_ = 0;
};

// The replies' quality fields, and the timings (which the sheet summary
// reports apart).
json QualityWithTimings(const FlattenQuality& q) {
  json j = QualityJson(q);
  j["distance_ms"] = q.distance_ms;
  j["solve_ms"] = q.solve_ms;
  j["total_ms"] = q.total_ms;
  return j;
}

FlattenQuality QualityOf(const json& j) {
  FlattenQuality q;
  q.stress = j.at("stress").get<double>();
  q.max_edge_error = j.at("max_edge_error").get<double>();
  q.area_ratio_min = j.at("area_ratio_min").get<double>();
  q.area_ratio_max = j.at("area_ratio_max").get<double>();
  q.folded_cells = j.at("folded_cells").get<int>();
  q.iterations = j.at("iterations").get<int>();
  q.converged = j.at("converged").get<bool>();
  q.distance_ms = j.at("distance_ms").get<double>();
  q.solve_ms = j.at("solve_ms").get<double>();
  q.total_ms = j.at("total_ms").get<double>();
  return q;
}

Status Corrupt(const std::string& what) {
  return Status(ErrorCode::kMalformed, "the shared sheet value " + what, "shared_tier");
}

}  // namespace

std::string SheetKey(std::string_view id) {
  return "surfdeform:sheet:v" + std::to_string(kSheetFormatVersion) + ":" SURFDEFORM_VERSION ":" +
         std::string(id);
}

std::string SheetLockKey(std::string_view id) { return SheetKey(id) + ":lock"; }

std::string EncodeSheet(const FlatSheet& sheet, const EncodedSheetParts& parts) {
  const json meta = {{"request", parts.canonical_request},
                     {"flatten_ms", parts.flatten_ms},
                     {"method", sheet.method},
                     {"frame",
                      {sheet.frame_linear(0, 0), sheet.frame_linear(1, 0), sheet.frame_linear(0, 1),
                       sheet.frame_linear(1, 1), sheet.frame_offset.x(), sheet.frame_offset.y()}},
                     {"period_u", {sheet.period_u.x(), sheet.period_u.y()}},
                     {"period_v", {sheet.period_v.x(), sheet.period_v.y()}},
                     {"quality", QualityWithTimings(sheet.quality)},
                     {"mesh_pairs", parts.mesh_pairs},
                     {"mesh_dropped_pairs", parts.mesh_dropped_pairs}};
  Writer w;
  w.Bytes(kMagic, sizeof kMagic);
  w.U32(kSheetFormatVersion);
  w.Text(SURFDEFORM_VERSION);
  w.Text(meta.dump());
  w.U32(static_cast<uint32_t>(sheet.nu));
  w.U32(static_cast<uint32_t>(sheet.nv));
  w.Vectors(sheet.points);
  w.Vectors(sheet.normals);
  w.Vectors(sheet.flat);
  w.U32(static_cast<uint32_t>(parts.mesh_flat.size()));
  w.Vectors(parts.mesh_flat);
  return w.Finish();
}

Result<DecodedSheet> DecodeSheet(std::string_view bytes, int max_grid_side,
                                 size_t max_mesh_vertices) {
  if (bytes.size() < sizeof kMagic + kChecksumDigits) return Corrupt("is too short");
  const std::string_view body = bytes.substr(0, bytes.size() - kChecksumDigits);
  if (std::memcmp(body.data(), kMagic, sizeof kMagic) != 0) return Corrupt("is not a sheet");
  if (proto::Sha256Hex(body, kChecksumDigits) != bytes.substr(body.size())) {
    return Corrupt("fails its checksum");
  }
  Reader r(body.substr(sizeof kMagic));
  uint32_t format = 0;
  std::string version, meta_text;
  if (!r.U32(&format) || format != kSheetFormatVersion) return Corrupt("has another format");
  if (!r.Text(&version, 64) || version != SURFDEFORM_VERSION) {
    return Corrupt("was written by another engine version");
  }
  if (!r.Text(&meta_text, body.size())) return Corrupt("is truncated in its header");
  uint32_t nu = 0, nv = 0;
  if (!r.U32(&nu) || !r.U32(&nv) || nu < 2 || nv < 2 || nu > static_cast<uint32_t>(max_grid_side) ||
      nv > static_cast<uint32_t>(max_grid_side)) {
    return Corrupt("has a grid size out of range");
  }
  DecodedSheet out;
  FlatSheet& s = out.sheet;
  s.nu = static_cast<int>(nu);
  s.nv = static_cast<int>(nv);
  const size_t n = size_t{nu} * nv;
  if (!r.Vectors(n, &s.points) || !r.Vectors(n, &s.normals) || !r.Vectors(n, &s.flat)) {
    return Corrupt("has truncated or non-finite samples");
  }
  uint32_t mesh_vertices = 0;
  if (!r.U32(&mesh_vertices) || mesh_vertices > max_mesh_vertices ||
      !r.Vectors(mesh_vertices, &out.parts.mesh_flat)) {
    return Corrupt("has a truncated, oversized or non-finite mesh sheet");
  }
  if (r.left() != 0) return Corrupt("has bytes after its samples");
  const json meta = json::parse(meta_text, nullptr, false);
  if (meta.is_discarded() || !meta.is_object()) return Corrupt("has an unreadable header");
  try {
    out.parts.canonical_request = meta.at("request").get<std::string>();
    out.parts.flatten_ms = meta.at("flatten_ms").get<double>();
    s.method = meta.at("method").get<std::string>();
    const json& f = meta.at("frame");
    if (!f.is_array() || f.size() != 6) return Corrupt("has a malformed frame");
    s.frame_linear << f[0].get<double>(), f[2].get<double>(), f[1].get<double>(),
        f[3].get<double>();
    s.frame_offset = Vec2(f[4].get<double>(), f[5].get<double>());
    for (auto [key, period] : {std::pair{"period_u", &s.period_u}, {"period_v", &s.period_v}}) {
      const json& t = meta.at(key);
      if (!t.is_array() || t.size() != 2) return Corrupt("has a malformed period");
      *period = Vec2(t[0].get<double>(), t[1].get<double>());
    }
    if (!s.frame_linear.allFinite() || !s.frame_offset.allFinite() || !s.period_u.allFinite() ||
        !s.period_v.allFinite()) {
      return Corrupt("has a non-finite frame");
    }
    s.quality = QualityOf(meta.at("quality"));
    out.parts.mesh_pairs = meta.at("mesh_pairs").get<size_t>();
    out.parts.mesh_dropped_pairs = meta.at("mesh_dropped_pairs").get<size_t>();
  } catch (const json::exception&) {
    return Corrupt("has a header with missing or mistyped fields");
  }
  return out;
}

}  // namespace surfdeform
