// The request types of the HTTP API and their JSON mapping (proto/openapi.yaml
// is the contract; this is its C++ side, shared by the server and the client).
// The requests are built from plain vocabulary shared with the engine: the
// surface description (surface_spec.hpp, animation_spec.hpp) and each
// option group's settings (*_settings.hpp, sampling_options.hpp,
// draco_options.hpp), whose field names are the JSON's, one to one, and
// whose own validation gives the value rules. Never the algorithms' option
// structs: how work runs (threads, time budgets, output limits, the input's
// axis convention) is the service's to add when it maps a request to the
// engine (service/engine_options.hpp). Parsing is strict: unknown fields and
// wrong types are kMalformed errors naming the JSON path.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "base/status.hpp"
#include "engine/animation/animation_spec.hpp"
#include "engine/common/placement_settings.hpp"
#include "engine/flatten/flatten_settings.hpp"
#include "engine/subdivision/subdivision_settings.hpp"
#include "engine/surface/sampling_options.hpp"
#include "engine/surface/surface_spec.hpp"
#include "meshio/draco_options.hpp"
#include "part/part_settings.hpp"
#include "text/text_settings.hpp"

namespace surfdeform::proto {

// The surface kinds of the API (`surface.kind`): the engine's table
// (engine/surface_spec.hpp).
using ::surfdeform::kSurfaceKinds;
using ::surfdeform::SurfaceKind;

// POST /v1/surfaces, and the surface part of POST /v1/deform.
struct SurfaceRequest {
  SurfaceSpec surface;
  SamplingOptions sampling;
  FlattenSettings flatten;
};

// Output formats: Draco .drc, GLB with KHR_draco_mesh_compression, plain GLB,
// OBJ, PLY.
enum class OutputFormat { kDrc, kGlb, kGlbPlain, kObj, kPly, kStl, k3mf };
inline constexpr EnumEntry<OutputFormat> kOutputFormats[] = {
    {OutputFormat::kDrc, "drc", "Draco bitstream (application/octet-stream)"},
    {OutputFormat::kGlb, "glb", "GLB with KHR_draco_mesh_compression"},
    {OutputFormat::kGlbPlain, "glb_plain", "GLB without compression"},
    {OutputFormat::kObj, "obj", "Wavefront OBJ"},
    {OutputFormat::kPly, "ply", "binary PLY"},
    {OutputFormat::kStl, "stl", "binary STL, in millimetres (model/stl)"},
    {OutputFormat::k3mf, "3mf", "3MF, unit millimetre, one object (model/3mf)"},
};
const char* OutputFormatName(OutputFormat format);  // from kOutputFormats
const char* OutputMediaType(OutputFormat format);

// output.compression: how a GLB's vertex data are compressed.
enum class GlbCompression { kDraco, kMeshopt, kNone };
inline constexpr EnumEntry<GlbCompression> kGlbCompressions[] = {
    {GlbCompression::kDraco, "draco",
     "KHR_draco_mesh_compression on each primitive (POST /v1/deform's default; not for "
     "animations)"},
    {GlbCompression::kMeshopt, "meshopt",
     "quantized attributes (KHR_mesh_quantization) in buffer views compressed with "
     "EXT_meshopt_compression (POST /v1/animate's default): some 10x faster to encode than "
     "Draco; three.js decodes it with MeshoptDecoder"},
    {GlbCompression::kNone, "none",
     "meshopt's layout uncompressed (quantized attributes), for validators and tools that do not "
     "know EXT_meshopt_compression"},
};

struct OutputOptions {
  std::optional<OutputFormat> format;  // unset: from the Accept header, else drc
  DracoOptions draco;
  bool draco_given = false;  // "draco" was in the request (it belongs to Draco output)
  bool distortion = false;   // per-vertex distortion of the map (glb, glb_plain, ply only)
  // How a GLB's vertex data are compressed: on POST /v1/deform draco unless
  // given (then the format is glb); on POST /v1/animate meshopt or none.
  std::optional<GlbCompression> compression;
};

// An animated surface: its keyframes, and the sampling and flattening of
// every frame (POST /v1/animate, and POST /v1/deform with a frame).
struct AnimationRequest {
  AnimationSpec animation;
  SamplingOptions sampling;
  FlattenSettings flatten;
};

// POST /v1/deform parameters: a surface inline (with its sampling and
// flattening) or the id of a flattened one, and what to do with the mesh.
struct DeformParams {
  // The mesh: from POST /v1/models by its id, or (empty) the request's body,
  // or made from a text (then placement.up defaults to +z and the anchor to
  // the letters' bottom: they stand on the surface).
  std::string model_id;
  std::optional<TextSettings> text;
  std::optional<SurfaceRequest> surface;  // inline ...
  std::string surface_id;                 // ... or by id ...
  // With an inline surface: an edit of this flattened surface. Its sheet is
  // where the flattening starts (as POST /v1/surfaces's "warm_start"), and
  // the one the placement's centre and rotation are given on: they are moved
  // onto the new sheet by the sheet's motion (not part of the answer's key:
  // the moved placement is).
  std::string warm_start;
  std::optional<AnimationRequest> animation;  // ... or one frame of an animation
  int frame = -1;                             // with animation: which, 0 .. frames - 1
  PlacementSettings placement;
  SubdivisionSettings subdivision;
  OutputOptions output;
};

// POST /v1/animate parameters: the animation, and what to do with the mesh
// (output: GLB only, with its compression).
struct AnimateParams {
  std::string model_id;  // as in DeformParams
  std::optional<TextSettings> text;
  AnimationRequest animation;
  PlacementSettings placement;
  SubdivisionSettings subdivision;
  OutputOptions output;
};

// POST /v1/surfaces's body: the surface request, and the id of a flattened
// surface to start from ("warm_start": an edit of it; not part of the id).
struct CreateSurfaceRequest {
  SurfaceRequest request;
  std::string warm_start;
};
Result<CreateSurfaceRequest> ParseCreateSurfaceRequest(const nlohmann::json& body);

// Parse the request bodies. `body` is an object with "surface", "sampling"
// and "flatten" (POST /v1/surfaces), or the deform parameters.
Result<SurfaceRequest> ParseSurfaceRequest(const nlohmann::json& body);
Result<DeformParams> ParseDeformParams(const nlohmann::json& body);
Result<AnimateParams> ParseAnimateParams(const nlohmann::json& body);

// POST /v1/parts: one closed solid, its body grown from a surface given
// inline ("surface") or by id ("surface_id"), sampled by "sampling" (the
// body's own grid), "body": {thickness_mm, side}; or an uploaded closed
// mesh, "body": {model_id}. "printer": {min_wall_mm, min_detail_mm},
// "strict", "output": {format}.
struct PartRequest {
  std::optional<SurfaceSpec> surface;
  std::string surface_id;
  std::string body_model_id;  // an uploaded body (POST /v1/models); then no surface
  // The body's own grid; unset: as the surface bends (BodySamples).
  std::optional<SamplingOptions> sampling;
  PartSettings part;
  OutputOptions output;
};
Result<PartRequest> ParsePartRequest(const nlohmann::json& body);

// The request bodies as JSON, which the parsers above read back into the
// same requests: every field written, with its default when not given (the
// client builds its requests with these). Only what a client may send:
// output.draco when it was given, output.format and output.compression when
// set.
nlohmann::json ToJson(const CreateSurfaceRequest& request);
nlohmann::json ToJson(const DeformParams& params);
nlohmann::json ToJson(const AnimateParams& params);

// Canonical forms of the deformation's options, as the engine reads them
// (every default filled in; scale "fit" with its margin, or a number): the
// request bodies above and the answers' keys (proto/answer_key.hpp).
nlohmann::json CanonicalJson(const PlacementSettings& placement);
nlohmann::json CanonicalJson(const SubdivisionSettings& subdivision);
nlohmann::json CanonicalJson(const DracoOptions& draco);

// The surface request with every default filled in, in a canonical form
// (sorted keys, shortest round-trip numbers): equal requests, equal text.
nlohmann::json CanonicalJson(const SurfaceRequest& request);

// The content hash that identifies a flattened surface: SHA-256 of the
// canonical form (and the flattening algorithm's version), 32 hex digits.
// The same on every replica.
std::string SurfaceId(const SurfaceRequest& request);

// The same for an animation's sheets: the canonical form of its keyframes,
// interpolation, frames and fps (a single wave key advances by 1 / fps),
// sampling and flattening.
nlohmann::json CanonicalJson(const AnimationRequest& request);
std::string AnimationId(const AnimationRequest& request);

// True for a string that has the shape of a SurfaceId (or a ModelId).
bool IsSurfaceIdShaped(std::string_view text);

// The id of an uploaded model (POST /v1/models): the first 32 hex digits of
// SHA-256 of the mesh file's bytes, nothing else, so that a client can
// compute it before uploading (and a load balancer route by it).
std::string ModelId(std::string_view mesh_bytes);

}  // namespace surfdeform::proto
