#include "service/field_encoding.hpp"

#include <bit>
#include <charconv>
#include <cmath>

#include "service/replies.hpp"

namespace surfdeform {
namespace {

// Appends numbers as float32 text and remembers the first that is not finite.
class FloatWriter {
 public:
  explicit FloatWriter(std::string* out) : out_(out) {}

  // `v` at float32 precision: the shortest text that reads back as it.
  void Number(double v, std::string_view key, size_t k, int c) {
    const float x = static_cast<float>(v);
    if (!std::isfinite(x)) {
      if (bad_.empty()) {
        bad_.assign(key);
        if (k != kNone) Index(k);
        Index(static_cast<size_t>(c));
      }
      out_->push_back('0');
      return;
    }
    char text[32];
    const auto r = std::to_chars(text, text + sizeof text, x);
    out_->append(text, r.ptr);
  }

  // The list `key` of n-vectors: [[x, y, ...], ...].
  template <typename V>
  void Vectors(std::string_view key, const std::vector<V>& values) {
    Key(key);
    out_->push_back('[');
    for (size_t k = 0; k < values.size(); ++k) {
      if (k > 0) out_->push_back(',');
      out_->push_back('[');
      for (int c = 0; c < values[k].size(); ++c) {
        if (c > 0) out_->push_back(',');
        Number(values[k][c], key, k, c);
      }
      out_->push_back(']');
    }
    out_->push_back(']');
  }

  void Key(std::string_view key) {
    if (out_->size() > 1) out_->push_back(',');
    out_->push_back('"');
    out_->append(key);
    out_->append("\":");
  }

  const std::string& bad() const { return bad_; }
  static constexpr size_t kNone = static_cast<size_t>(-1);

 private:
  void Index(size_t k) {
    bad_.push_back('[');
    bad_.append(std::to_string(k));
    bad_.push_back(']');
  }

  std::string* out_;
  std::string bad_;
};

}  // namespace

Result<std::string> FieldJsonText(const SheetField& f, std::string_view path) {
  std::string out;
  out.reserve(64 + f.positions.size() * 100);
  out.push_back('{');
  FloatWriter w(&out);
  // Keys in order, as the service's other JSON writes them.
  w.Key("bounds");
  out.append("[[");
  w.Number(f.lo.x(), "bounds", 0, 0);
  out.push_back(',');
  w.Number(f.lo.y(), "bounds", 0, 1);
  out.append("],[");
  w.Number(f.hi.x(), "bounds", 1, 0);
  out.push_back(',');
  w.Number(f.hi.y(), "bounds", 1, 1);
  out.append("]]");
  w.Key("n");
  out.append(std::to_string(f.n));
  w.Vectors("normals", f.normals);
  w.Key("on_sheet");
  out.push_back('[');
  for (size_t k = 0; k < f.on_sheet.size(); ++k) {
    if (k > 0) out.push_back(',');
    out.append(f.on_sheet[k] != 0 ? "true" : "false");
  }
  out.push_back(']');
  w.Vectors("params", f.params);
  w.Vectors("positions", f.positions);
  out.push_back('}');
  if (!w.bad().empty()) {
    return NonFiniteNumber("reply", path.empty() ? w.bad() : std::string(path) + "." + w.bad());
  }
  return out;
}

std::string WithMember(std::string object, std::string_view key, std::string_view value) {
  const size_t end = object.rfind('}');
  if (end == std::string::npos) return object;
  std::string member;
  member.reserve(key.size() + value.size() + 4);
  if (object.find_first_not_of(" \t\r\n", object.find('{') + 1) != end) member.push_back(',');
  member.push_back('"');
  member.append(key);
  member.append("\":");
  member.append(value);
  object.insert(end, member);
  return object;
}

std::string FieldBinary(const SheetField& f) {
  static_assert(std::endian::native == std::endian::little,
                "the field's bytes are little-endian numbers as they are in memory");
  std::string out("SDFD", 4);
  auto u32 = [&out](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); };
  auto f32 = [&out](double v) {
    const float x = static_cast<float>(v);
    out.append(reinterpret_cast<const char*>(&x), sizeof x);
  };
  const size_t count = f.positions.size();
  out.reserve(32 + count * 33);
  u32(kFieldFormatVersion);
  u32(static_cast<uint32_t>(f.n));
  u32(0);
  for (double v : {f.lo.x(), f.lo.y(), f.hi.x(), f.hi.y()}) f32(v);
  for (const Vec3& p : f.positions)
    for (int c = 0; c < 3; ++c) f32(p[c]);
  for (const Vec3& q : f.normals)
    for (int c = 0; c < 3; ++c) f32(q[c]);
  out.append(reinterpret_cast<const char*>(f.on_sheet.data()), f.on_sheet.size());
  for (const Vec2& uv : f.params)
    for (int c = 0; c < 2; ++c) f32(uv[c]);
  return out;
}

}  // namespace surfdeform
