// The sheet's field (engine/sheet_field.hpp) as a reply: JSON text or bytes.
// A live edit asks for the field with every pointer move (POST
// /v1/surfaces?field=64: 4,096 lattice points, ~37,000 numbers), so the JSON
// is written directly rather than built as a JSON tree: the tree and its
// round trip of each number through text cost ten times the flattening.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "base/status.hpp"
#include "engine/sheet/sheet_field.hpp"

namespace surfdeform {

// GET /v1/surfaces/{id}/field as JSON: {"bounds": [[xmin, ymin], [xmax,
// ymax]], "n", "normals", "on_sheet", "params", "positions"}, n * n entries
// each, x fastest. Numbers at float32 precision, each the shortest text that
// reads back as the same float32 (what the bytes carry). kInvalidArgument,
// naming the number as `path`.key[k][c], where one is past float32's range.
Result<std::string> FieldJsonText(const SheetField& f, std::string_view path = "");

// `object` (a JSON object's text) with the member `key`: `value` (JSON text)
// added at its end.
std::string WithMember(std::string object, std::string_view key, std::string_view value);

// The same as bytes (application/octet-stream), all little-endian:
//   0  "SDFD" (4 bytes), uint32 version (2), uint32 n, uint32 flags (0),
//  16  float32 xmin, ymin, xmax, ymax,
//  32  float32 positions[n * n][3], then float32 normals[n * n][3],
//      then uint8 on_sheet[n * n] (1: on the sheet),
//      then float32 params[n * n][2] (the surface's u, v; version 2 on).
// Version 2 appends the params: a version 1 reader's offsets still hold.
inline constexpr uint32_t kFieldFormatVersion = 2;
std::string FieldBinary(const SheetField& f);

}  // namespace surfdeform
