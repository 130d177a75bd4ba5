// A flattened surface as bytes for the shared tier (Redis): the canonical
// surface request it answers, the sheet, and a checksum. Values are written
// by one replica and read by others, possibly of another version, so
// decoding trusts nothing: a value of another format or engine version, a
// bad checksum, a truncated array or a non-finite number is refused.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "base/status.hpp"
#include "engine/flatten/flatten.hpp"

namespace surfdeform {

// 2: the period of a periodic sheet; 3: a mesh surface's flat vertices.
inline constexpr int kSheetFormatVersion = 3;

// The Redis key of surface `id`: format and engine version are part of it,
// so replicas of different versions never read each other's values.
std::string SheetKey(std::string_view id);
std::string SheetLockKey(std::string_view id);

struct EncodedSheetParts {
  std::string canonical_request;  // proto::CanonicalJson(request).dump()
  double flatten_ms = 0.0;
  // A surface given as a mesh: each vertex's flat position (FlatMesh::flat),
  // what another replica needs besides the mesh to rebuild the surface
  // without flattening it; empty for every other kind.
  std::vector<Vec2> mesh_flat;
  size_t mesh_pairs = 0, mesh_dropped_pairs = 0;  // FlatMesh's counts, for the summary
};

std::string EncodeSheet(const FlatSheet& sheet, const EncodedSheetParts& parts);

struct DecodedSheet {
  FlatSheet sheet;
  EncodedSheetParts parts;
};

// kMalformed, naming what is wrong, for anything but a value EncodeSheet of
// this version wrote. `max_grid_side` and `max_mesh_vertices` bound the
// arrays before they are read.
Result<DecodedSheet> DecodeSheet(std::string_view bytes, int max_grid_side,
                                 size_t max_mesh_vertices = 10'000'000);

}  // namespace surfdeform
