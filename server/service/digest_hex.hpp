// A 128-bit xxHash digest as 32 hex digits (the keys of the service's
// in-process memos: sheets, topologies).
#pragma once

#include <xxhash.h>

#include <cstdio>
#include <string>

namespace surfdeform {

inline std::string DigestHex(const XXH128_hash_t& digest) {
  char text[33];
  std::snprintf(text, sizeof text, "%016llx%016llx", static_cast<unsigned long long>(digest.high64),
                static_cast<unsigned long long>(digest.low64));
  return text;
}

}  // namespace surfdeform
