// Internal: one reader per format, called by ImportMesh once the format is
// known and the byte limit checked. Each returns what it read or an error.
#pragma once

#include <string_view>

#include "meshio/mesh_import.hpp"

namespace surfdeform::meshio {

Result<ImportedMesh> ReadObj(std::string_view bytes, const ImportLimits& limits);
Result<ImportedMesh> ReadPly(std::string_view bytes, const ImportLimits& limits);
Result<ImportedMesh> ReadStl(std::string_view bytes, const ImportLimits& limits);
Result<ImportedMesh> ReadOff(std::string_view bytes, const ImportLimits& limits);
Result<ImportedMesh> ReadDraco(std::string_view bytes, const ImportLimits& limits);
Result<ImportedMesh> ReadGltf(std::string_view bytes, bool binary, const ImportLimits& limits);

// `text` with every byte that is not part of a valid UTF-8 sequence replaced
// by '?', and cut to `max_bytes`: names from files end up in JSON (GLB) and
// in messages, which must stay valid.
std::string CleanName(std::string_view text, size_t max_bytes = 256);

// kLimitExceeded when `actual` is over `limit`, naming what was counted.
Status CheckLimit(const char* what, size_t actual, size_t limit);

// The most corners a polygon (an OBJ or PLY face) may have: AppendPolygon's
// callers keep its corners on the stack.
inline constexpr size_t kMaxPolygon = 256;

// Appends the triangulation of a polygon (indices already checked) whose
// corners lie at `positions`: ear clipping in the polygon's best-fit plane,
// so concave polygons come out right; a fan where ear clipping finds no ear
// (self-intersecting or degenerate polygons).
void AppendPolygon(const uint32_t* corners, const Vec3* positions, size_t count, Mesh* mesh);

}  // namespace surfdeform::meshio
