// Reading untrusted JSON text (a request's parameters, a glTF's JSON chunk)
// into a document, in time linear in its bytes and in memory bounded by its
// limits, whatever its shape.
//
// The text is read by nlohmann's SAX parser into a document built here (not
// through nlohmann's callback parser, which rescans the parent container at
// every closing bracket: quadratic in the elements of an array). Each limit
// is checked as the text is read, so that a hostile body stops at the first
// element past a limit; a duplicate key is found by the object's own lookup
// and its path is spelled only then.
#pragma once

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "base/status.hpp"

namespace surfdeform {

struct JsonLimits {
  int max_depth = 32;  // nesting of objects and arrays
  // Values of any kind (numbers, strings, objects, arrays, ...): a surface
  // of kMaxControlPoints [x, y, z] points is 4 of them a point.
  size_t max_elements = 5'000'000;
  // The bytes of every key and string together, as decoded.
  size_t max_string_bytes = 16u << 20;
  // Members left out of the document as they are read (not counted against
  // the limits, never allocated): called with the key of the object that
  // holds the member (empty at the top, or inside an array) and the
  // member's key. Empty: every member is kept.
  std::function<bool(std::string_view parent_key, std::string_view key)> skip_member;
};

// Called after every kJsonCheckpointValues values while the text is read:
// an error (a spent time budget, a cancelled request) stops the parse with
// it.
using JsonCheckpoint = std::function<Status()>;
inline constexpr size_t kJsonCheckpointValues = 4096;

// Parses JSON text. kMalformed for a syntax error (with its byte
// offset), a key given twice in one object (naming its path), or a nesting
// deeper than max_depth; kLimitExceeded (with the limit and the count so
// far) past max_elements or max_string_bytes; kInvalidArgument for a number
// beyond the range of doubles; the checkpoint's error when it fails. `what`
// names the document in messages and fields ("params", "body").
// `skipped`, when given, counts the members left out.
Result<nlohmann::json> ParseBoundedJson(std::string_view text, const JsonLimits& limits,
                                        const std::string& what,
                                        const JsonCheckpoint& checkpoint = {},
                                        size_t* skipped = nullptr);

// "a.b" and "a[3]": a JSON path from its parent's path and a key or index.
std::string JsonPath(const std::string& parent, std::string_view key);
std::string JsonPath(const std::string& parent, size_t index);

}  // namespace surfdeform
