// The fonts a text may name: the built-in ones (Debian's font files, read
// once at start from the font directory) and uploaded ones (POST
// /v1/fonts), kept by content id like models: an LRU in process, the shared
// tier (Redis or the disk) under it, so replicas share them and a restart
// keeps them.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.hpp"
#include "service/service_limits.hpp"
#include "service/shared_tier.hpp"
#include "service/single_flight_cache.hpp"
#include "text/font_face.hpp"

namespace surfdeform {

struct StoredFont {
  std::string id;    // SHA-256 of the bytes, 32 hex digits (proto::ModelId)
  std::string name;  // a built-in's name; empty for an upload
  std::shared_ptr<const std::string> bytes;
  FontInfo info;
  size_t bytes_held = 0;
};

class FontStore {
 public:
  // Reads the built-in fonts under limits.font_dir; one that is missing is
  // left out of the list (`missing` names them, for the log).
  FontStore(const ServiceLimits& limits, std::shared_ptr<SharedTier> shared);
  FontStore(const FontStore&) = delete;
  FontStore& operator=(const FontStore&) = delete;

  // A built-in font by name, or an uploaded one by id. kInvalidArgument
  // naming `field` (a 422 listing the built-in fonts) for neither.
  Result<std::shared_ptr<const StoredFont>> Find(std::string_view name_or_id,
                                                 const std::string& field);

  // POST /v1/fonts: the font read behind the limits (a 400 for a broken
  // one), kept, and written to the shared tier. *known: it was held before.
  Result<std::shared_ptr<const StoredFont>> Put(std::string_view bytes, bool* known);

  const std::vector<std::shared_ptr<const StoredFont>>& builtin() const { return builtin_; }
  const std::vector<std::string>& missing() const { return missing_; }

  // The built-in fonts that have every one of `code_points`.
  std::vector<std::string> BuiltinsWith(const std::u32string& code_points) const;

  CacheStats stats() const { return uploaded_.stats(); }

 private:
  // The font of `bytes`, read by FreeType within the font limits; the face
  // it opened goes to `*face` when given (the built-ins keep theirs).
  Result<std::shared_ptr<const StoredFont>> Read(const std::string& id,
                                                 std::shared_ptr<const std::string> bytes,
                                                 std::string name,
                                                 std::unique_ptr<FontFace>* face = nullptr);

  const ServiceLimits limits_;
  const std::shared_ptr<SharedTier> shared_;
  std::vector<std::shared_ptr<const StoredFont>> builtin_;
  std::vector<std::string> missing_;
  // One open face per built-in font, for BuiltinsWith (FreeType's faces
  // are one thread's at a time).
  mutable std::mutex faces_mutex_;
  std::vector<std::unique_ptr<FontFace>> faces_;
  SingleFlightCache<StoredFont> uploaded_;
};

}  // namespace surfdeform
