// SHA-256 (OpenSSL), for ids and ETags that must be the same on every replica.
#pragma once

#include <string>
#include <string_view>

namespace surfdeform::proto {

// The first `hex_digits` (at most 64) lowercase hex digits of SHA-256(bytes).
std::string Sha256Hex(std::string_view bytes, size_t hex_digits = 64);

}  // namespace surfdeform::proto
