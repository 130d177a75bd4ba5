#include "service/font_store.hpp"

#include <fstream>
#include <sstream>

#include "proto/api.hpp"
#include "service/model_codec.hpp"

namespace surfdeform {
namespace {

// Uploaded fonts in the shared tier: the file's bytes behind the models'
// envelope (model_codec.hpp), under keys of their own.
std::string FontKey(std::string_view id) { return "font:" + ModelKey(id); }

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

FontStore::FontStore(const ServiceLimits& limits, std::shared_ptr<SharedTier> shared)
    : limits_(limits),
      shared_(std::move(shared)),
      uploaded_(limits.font_cache_bytes, [](const StoredFont& f) { return f.bytes_held; }) {
  for (const BuiltinFont& b : kBuiltinFonts) {
    auto bytes = std::make_shared<const std::string>(ReadWholeFile(limits.font_dir + "/" + b.file));
    if (bytes->empty()) {
      missing_.push_back(std::string(b.name) + " (" + limits.font_dir + "/" + b.file +
                         ", Debian package " + b.package + ")");
      continue;
    }
    std::unique_ptr<FontFace> face;
    auto font = Read(proto::ModelId(*bytes), bytes, b.name, &face);
    if (!font.ok()) {
      missing_.push_back(std::string(b.name) + ": " + font.status().message());
      continue;
    }
    builtin_.push_back(*font);
    faces_.push_back(std::move(face));  // opened once, beside its font
  }
}

Result<std::shared_ptr<const StoredFont>> FontStore::Read(const std::string& id,
                                                          std::shared_ptr<const std::string> bytes,
                                                          std::string name,
                                                          std::unique_ptr<FontFace>* face_out) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto face, FontFace::Open(*bytes, limits_.font));
  auto font = std::make_shared<StoredFont>();
  font->id = id;
  font->name = std::move(name);
  font->info = face->info();
  font->bytes_held = bytes->size() + 1024;
  font->bytes = std::move(bytes);
  if (face_out != nullptr) *face_out = std::move(face);
  return std::shared_ptr<const StoredFont>(std::move(font));
}

Result<std::shared_ptr<const StoredFont>> FontStore::Find(std::string_view name_or_id,
                                                          const std::string& field) {
  for (const auto& f : builtin_) {
    if (f->name == name_or_id) return f;
  }
  if (proto::IsSurfaceIdShaped(name_or_id)) {
    const std::string id(name_or_id);
    bool hit = false;
    auto found = uploaded_.GetOrCompute(
        id,
        [&]() -> Result<std::shared_ptr<const StoredFont>> {
          std::string value;
          if (shared_ == nullptr || shared_->Get(FontKey(id), &value) != SharedTier::Lookup::kHit) {
            return Status(ErrorCode::kNotFound, "no font");
          }
          auto file = DecodeModel(value, id, limits_.font.max_font_bytes);
          if (!file.ok()) {
            shared_->CountCorrupt();
            return Status(ErrorCode::kNotFound, "no font");
          }
          return Read(id, std::make_shared<const std::string>(std::move(*file)), "");
        },
        &hit);
    if (found.ok()) return *found;
  }
  std::string names;
  for (const auto& f : builtin_) names += (names.empty() ? "" : ", ") + f->name;
  return Status(ErrorCode::kInvalidArgument,
                "names no built-in font and no uploaded font held here (evicted, or never "
                "uploaded: POST it to /v1/fonts); the built-in fonts are " +
                    names,
                field);
}

Result<std::shared_ptr<const StoredFont>> FontStore::Put(std::string_view bytes, bool* known) {
  if (bytes.size() > limits_.font.max_font_bytes) {
    return Status::LimitExceeded("the font file is larger than the limit", "font",
                                 static_cast<double>(limits_.font.max_font_bytes),
                                 static_cast<double>(bytes.size()));
  }
  const std::string id = proto::ModelId(bytes);
  bool in_shared = false;
  auto result = uploaded_.GetOrCompute(
      id,
      [&]() -> Result<std::shared_ptr<const StoredFont>> {
        SURFDEFORM_ASSIGN_OR_RETURN(auto font,
                                    Read(id, std::make_shared<const std::string>(bytes), ""));
        if (shared_ != nullptr) {
          in_shared = shared_->Exists(FontKey(id));
          if (!in_shared) shared_->Put(FontKey(id), EncodeModel(bytes));
        }
        return font;
      },
      known);
  if (in_shared) *known = true;
  return result;
}

std::vector<std::string> FontStore::BuiltinsWith(const std::u32string& code_points) const {
  std::vector<std::string> out;
  std::lock_guard lock(faces_mutex_);
  for (size_t k = 0; k < faces_.size() && k < builtin_.size(); ++k) {
    bool all = true;
    for (char32_t c : code_points) all = all && faces_[k]->HasCodePoint(c);
    if (all) out.push_back(builtin_[k]->name);
  }
  return out;
}

}  // namespace surfdeform
