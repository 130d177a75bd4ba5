// An uploaded model as bytes for the shared tier (Redis): the mesh file as
// it was uploaded, behind a magic number and a format version. Values are
// written by one replica and read by others, possibly of another version, so
// decoding trusts nothing: a value of another format, a truncated one, or
// one whose bytes do not hash to the id it is stored under is refused (the
// id is SHA-256 of the bytes, so it is the value's checksum).
#pragma once

#include <string>
#include <string_view>

#include "base/status.hpp"

namespace surfdeform {

inline constexpr int kModelFormatVersion = 1;

// The Redis key of model `id`. The format version is part of it; the
// server's version is not: the bytes are the uploaded file's, and any
// version imports them.
std::string ModelKey(std::string_view id);

std::string EncodeModel(std::string_view file_bytes);

// The file's bytes, or kMalformed naming what is wrong. `max_bytes` bounds
// the length before anything is copied.
Result<std::string> DecodeModel(std::string_view value, std::string_view id, size_t max_bytes);

}  // namespace surfdeform
