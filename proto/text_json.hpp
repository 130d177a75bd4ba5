// The "text" model source of POST /v1/deform and /v1/animate as JSON
// (text/text_settings.hpp is the vocabulary): strict reading, and the
// canonical form that names a text's model in answers' keys.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>

#include "base/status.hpp"
#include "proto/json_object.hpp"
#include "text/text_settings.hpp"

namespace surfdeform::proto {

// Reads parent["text"] when present (then *out is set); errors name the
// JSON path ("text.size_mm").
Status ReadText(JsonObject& parent, std::optional<TextSettings>* out);

// POST /v1/text's body: the text, and the output format of its mesh
// (unset: from the Accept header).
struct TextRequest {
  TextSettings text;
  std::optional<std::string> format;  // an output format's name, checked by the caller
};
Result<TextRequest> ParseTextRequest(const nlohmann::json& body);

// Every field, with its default when not given, sorted keys: equal texts,
// equal JSON. ReadText reads it back into the same settings.
nlohmann::json CanonicalJson(const TextSettings& text);

}  // namespace surfdeform::proto
