// Which output format a deform request gets: the one its parameters name,
// else the first acceptable one in its Accept header, else Draco (.drc).
#pragma once

#include <optional>
#include <string_view>

#include "base/status.hpp"
#include "meshio/mesh_format.hpp"
#include "proto/api.hpp"

namespace surfdeform {

// Media types: application/octet-stream, application/x-draco,
// application/vnd.google.draco -> drc; model/gltf-binary, model/* -> glb
// (Draco-compressed); model/obj, text/plain -> obj; application/x-ply,
// application/ply -> ply; */*, application/* or no header -> drc. Types with
// q=0 are skipped. kNotAcceptable when the header names only other types.
Result<proto::OutputFormat> ChooseOutputFormat(std::optional<proto::OutputFormat> requested,
                                               std::string_view accept);

// For answers that are only ever a GLB (POST /v1/animate): Ok when the
// Accept header is empty or accepts model/gltf-binary, model/* or */* (not
// with q=0); else kNotAcceptable naming the header.
Status AcceptGlbOnly(std::string_view accept);

// For answers in JSON or bytes (GET /v1/surfaces/{id}/field): true when the
// first of application/octet-stream and application/json that the Accept
// header accepts (not with q=0) is application/octet-stream; JSON otherwise.
bool PrefersBytesToJson(std::string_view accept);

// output.distortion travels only in formats that name custom attributes
// (glb, glb_plain, ply); else kInvalidArgument naming the field.
Status CheckDistortionFormat(const proto::OutputOptions& output, proto::OutputFormat format);

// The writer of a format.
MeshFormat OutputMeshFormat(proto::OutputFormat format);

}  // namespace surfdeform
