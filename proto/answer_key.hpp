// The key of an encoded answer of POST /v1/deform: everything
// that determines its bytes, in a canonical text, so that equal requests
// have equal keys however they were written (defaults filled in, fields in
// any order, the model inline or by id, the format from "output" or from the
// Accept header). The answer cache (service/answer_cache.hpp) keeps answers
// by it, and the ETag is its digest, so that If-None-Match is decided before
// any work.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "proto/api.hpp"

namespace surfdeform::proto {

// The parts of an answer's key. `surface` names the sheet the model is laid
// on: its id and a digest of the sheet as the server holds it (a sheet
// warm-started from an edit has the id of its request, and may differ from a
// cold flattening within the solver's tolerance).
struct AnswerKeyParts {
  std::string_view model;    // the model's id (ModelId of its file's bytes)
  std::string_view surface;  // the surface id and its sheet's digest
  const PlacementSettings* placement = nullptr;
  const SubdivisionSettings* subdivision = nullptr;
  const OutputOptions* output = nullptr;
  OutputFormat format = OutputFormat::kDrc;  // as chosen (output.format or Accept)
  // The server's --glb-split-vertices: where a Draco GLB is cut into pieces.
  size_t glb_split_vertices = 0;
};

// The canonical form of the output options, as the encoders read them:
// only what the format uses (placement and subdivision: proto/api.hpp).
nlohmann::json CanonicalJson(const OutputOptions& output, OutputFormat format);

// The key's text, versioned: a change to the server that changes answers'
// bytes must change kAnswerVersion.
std::string AnswerKey(const AnswerKeyParts& parts);

// 32 hex digits of the key's SHA-256: the answer's ETag.
std::string AnswerEtag(std::string_view key);

// Whether an If-None-Match header names this ETag or its gzipped
// representation's ("<etag>-gzip") in its list of entity tags (weak ones
// compared weakly), RFC 9110 section 13.1.2. "*" names none here: an answer
// is computed, so "any representation exists" would skip every request's
// checks, the invalid ones' too.
bool IfNoneMatchNames(std::string_view if_none_match, std::string_view etag);

}  // namespace surfdeform::proto
