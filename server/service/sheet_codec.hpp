// A flattened surface as bytes for the shared tier (Redis): the canonical
// surface request it answers, the sheet, and a checksum. Values are written
// by one replica and read by others, possibly of another version, so
// decoding trusts nothing: a value of another format or engine version, a
// bad checksum, a truncated array or a non-finite number is refused.
#pragma once

#include <string>
#include <string_view>

#include "base/status.hpp"
#include "engine/flatten.hpp"

namespace surfdeform {

inline constexpr int kSheetFormatVersion = 2;  // 2: the period of a periodic sheet

// The Redis key of surface `id`: format and engine version are part of it,
// so replicas of different versions never read each other's values.
std::string SheetKey(std::string_view id);
std::string SheetLockKey(std::string_view id);

struct EncodedSheetParts {
  std::string canonical_request;  // proto::CanonicalJson(request).dump()
  double flatten_ms = 0.0;
};

std::string EncodeSheet(const FlatSheet& sheet, const EncodedSheetParts& parts);

struct DecodedSheet {
  FlatSheet sheet;
  EncodedSheetParts parts;
};

// kMalformed, naming what is wrong, for anything but a value EncodeSheet of
// this version wrote. `max_grid_side` bounds the arrays before they are read.
Result<DecodedSheet> DecodeSheet(std::string_view bytes, int max_grid_side);

}  // namespace surfdeform
