// The nesting depth of a JSON text, counted without parsing, so that a limit
// can be checked before a recursive parser (tinygltf, nlohmann) sees the text.
#pragma once

#include <string_view>

namespace surfdeform {

// The deepest nesting of objects and arrays in `json` (strings skipped).
int JsonNestingDepth(std::string_view json);

}  // namespace surfdeform
