#include "cli/commands.hpp"

#include <cctype>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "proto/content_hash.hpp"
#include "proto/map_api.hpp"

namespace surfdeform::cli {

using nlohmann::json;

int ExitFor(const HttpFailure& f) {
  if (f.unreachable || f.status >= 500) return kExitUnavailable;
  return kExitRefused;
}

void ConfigureRetries(const Connection& c, ApiClient* client) {
  if (!c.verbose) return;
  client->set_on_retry([](int attempt, const std::string& why, double wait) {
    std::fprintf(stderr, "retry %d: %s; waiting %.1f s\n", attempt, why.c_str(), wait);
  });
}

// JSON text, or the name of a file holding it.
bool ReadJsonArgument(const std::string& text_or_file, nlohmann::json* out, CliError* error) {
  std::string text = text_or_file;
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || (text[first] != '{' && text[first] != '[')) {
    if (!ReadFileBytes(text_or_file, &text, &error->message)) {
      error->kind = CliError::Kind::kLocalFile;
      return false;
    }
  }
  *out = json::parse(text, nullptr, false);
  if (out->is_discarded()) {
    *error = {CliError::Kind::kUsage,
              text_or_file.size() < 80 ? "not valid JSON: " + text_or_file : "not valid JSON"};
    return false;
  }
  return true;
}

// {"surface": ..., "sampling": ..., "flatten": ...} from a surface file: a
// whole surface request, a bare surface ({"kind": ...}), or a mesh file,
// which is the surface {"kind": "mesh", "model_id": <its id>} (its bytes to
// `mesh`, for the caller to upload).
bool ReadSurfaceRequest(const std::string& file, json* out, CliError* error, std::string* mesh) {
  if (IsMeshFileName(file) && mesh != nullptr) {
    std::string message;
    if (!ReadFileBytes(file, mesh, &message)) {
      *error = {CliError::Kind::kLocalFile, message};
      return false;
    }
    *out = {{"surface", {{"kind", "mesh"}, {"model_id", proto::Sha256Hex(*mesh, 32)}}}};
    return true;
  }
  json j;
  if (!ReadJsonArgument(file, &j, error)) return false;
  if (!j.is_object()) {
    *error = {CliError::Kind::kUsage, file + ": a surface file holds a JSON object"};
    return false;
  }
  *out = j.contains("surface") ? j : json{{"surface", j}};
  // The sample surfaces (client/web/samples) say what they are in a
  // "description", which is the file's, not the API's.
  if ((*out)["surface"].is_object()) (*out)["surface"].erase("description");
  return true;
}

// A request the API refuses: its field and message, as the server gives them.
CliError Refused(const Status& status) {
  return {CliError::Kind::kRefused,
          (status.field().empty() ? "" : status.field() + ": ") + status.message()};
}

namespace {

// The GLB compression named by --compression (`choices` lists those the
// command takes, for its usage error).
bool ReadCompression(const std::string& name, const char* choices, proto::GlbCompression* out,
                     CliError* error) {
  const auto c = ValueOf<proto::GlbCompression>(proto::kGlbCompressions, name);
  if (!c) {
    *error = {CliError::Kind::kUsage, std::string("--compression: ") + choices};
    return false;
  }
  *out = *c;
  return true;
}

// The flags of deform, batch and animate on a request read from --params
// (proto::DeformParams or proto::AnimateParams), for an output of `kind`;
// *decode: the reply is Draco to decode here into OBJ or PLY.
template <typename Params>
bool ApplyFlags(const DeformOptions& o, OutputKind kind, Params* p, bool* decode, CliError* error) {
  if (!o.model_id.empty()) p->model_id = o.model_id;
  if (!o.text.empty()) {
    TextSettings t;
    if (p->text) t = *p->text;
    t.string = o.text;
    if (!o.font.empty()) t.font = o.font;
    if (o.size_mm > 0.0) t.size_mm = o.size_mm;
    if (o.depth_mm >= 0.0) t.depth_mm = o.depth_mm;
    if (!p->text) {  // the parameters' placement defaults, as the server reads a text's
      if (p->placement.up == UpAxis::kAuto) p->placement.up = UpAxis::kPosZ;
      if (p->placement.anchor == AnchorMode::kCenter) p->placement.anchor = AnchorMode::kBottom;
    }
    p->text = std::move(t);
  }
  if (!o.subdivision.empty()) {
    const auto mode = ValueOf<SubdivisionMode>(kSubdivisionModes, o.subdivision);
    if (!mode) {
      *error = {CliError::Kind::kUsage, "--subdivision: off, adaptive or uniform"};
      return false;
    }
    p->subdivision.mode = *mode;
  }
  if (o.tolerance > 0.0) p->subdivision.tolerance = o.tolerance;
  if (o.scale == "fit") {
    p->placement.fit = true;
  } else if (!o.scale.empty()) {
    char* end = nullptr;
    const double s = std::strtod(o.scale.c_str(), &end);
    if (end == o.scale.c_str() || *end != '\0') {
      *error = {CliError::Kind::kUsage, "--scale: \"fit\" or a number, got " + o.scale};
      return false;
    }
    p->placement.fit = false;
    p->placement.scale = s;
  }
  proto::OutputOptions& output = p->output;
  const bool distortion = o.distortion || output.distortion;
  if (distortion) {
    if (kind != OutputKind::kGlb && kind != OutputKind::kPly) {
      *error = {CliError::Kind::kUsage,
                "--distortion: the distortion map is written in .glb and .ply output only"};
      return false;
    }
    output.distortion = true;
  }
  if (!o.compression.empty()) {
    if (kind != OutputKind::kGlb) {
      *error = {CliError::Kind::kUsage, "--compression: compresses .glb output only"};
      return false;
    }
    proto::GlbCompression c;
    if (!ReadCompression(o.compression, "draco, meshopt or none", &c, error)) return false;
    output.compression = c;
  }
  *decode = false;
  switch (kind) {
    case OutputKind::kDrc:
      output.format = proto::OutputFormat::kDrc;
      break;
    case OutputKind::kGlb:
      output.format = proto::OutputFormat::kGlb;
      break;
    case OutputKind::kObj:
    case OutputKind::kPly:
      if (o.lossless || distortion) {  // Draco would not carry the distortion map
        output.format =
            kind == OutputKind::kObj ? proto::OutputFormat::kObj : proto::OutputFormat::kPly;
      } else {
        // Draco over the wire (a fraction of the bytes), decoded here; the
        // sequential encoding keeps the vertex order.
        output.format = proto::OutputFormat::kDrc;
        output.draco.sequential = true;
        output.draco_given = true;
        *decode = true;
      }
      break;
  }
  return true;
}

// The request as it will be sent, read back: flags that make a request the
// API refuses (--scale -1, a compression with draco settings) are found here.
template <typename Params, typename Parse>
bool CheckAsSent(const Params& p, Parse parse, CliError* error) {
  Params again;
  return ReadRequest(proto::ToJson(p), parse, &again, error);
}

// The JSON reply of a request that creates something with an id; false,
// having said so, for anything else.
bool ReplyWithId(const HttpReply& r, json* out) {
  *out = json::parse(r.body, nullptr, false);
  if (!out->is_discarded() && out->contains("id")) return true;
  std::fprintf(stderr, "surfdeform: unexpected reply from the server\n");
  return false;
}

}  // namespace

int RunInfo(const Connection& c) {
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  HttpReply r;
  HttpFailure f;
  if (!client.Get("/v1/info", &r, &f)) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", c.server.c_str(), f.message.c_str());
    return ExitFor(f);
  }
  const json j = json::parse(r.body, nullptr, false);
  std::printf("%s\n", j.is_discarded() ? r.body.c_str() : j.dump(2).c_str());
  return kExitOk;
}

int RunHealth(const Connection& c) {
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  HttpReply r;
  HttpFailure f;
  if (!client.Get("/healthz", &r, &f)) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", c.server.c_str(), f.message.c_str());
    return ExitFor(f);
  }
  HttpReply ready;
  HttpFailure not_ready;
  const bool is_ready = client.Get("/readyz", &ready, &not_ready);
  std::printf("%s: live, %s\n", c.server.c_str(), is_ready ? "ready" : "not ready (draining)");
  return is_ready ? kExitOk : kExitUnavailable;
}

int RunMap(const Connection& c, const std::string& surface_id, const std::string& request,
           const std::string& out_path) {
  json body;
  CliError error;
  if (!ReadJsonArgument(request, &body, &error)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return error.exit_code();
  }
  // Read as the server reads it, but for its limits (its own, at /v1/info).
  proto::MapRequest parsed;
  auto parse = [](const json& j) { return proto::ParseMapRequest(j, proto::kNoMapLimits); };
  if (!ReadRequest(body, parse, &parsed, &error)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return error.exit_code();
  }
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  HttpReply r;
  HttpFailure f;
  if (!client.PostJson("/v1/surfaces/" + surface_id + "/map", proto::ToJson(parsed).dump(), &r,
                       &f)) {
    std::fprintf(stderr, "surfdeform: %s\n", f.message.c_str());
    return ExitFor(f);
  }
  const json j = json::parse(r.body, nullptr, false);
  const std::string text = (j.is_discarded() ? r.body : j.dump(2)) + "\n";
  if (out_path.empty()) {
    std::fwrite(text.data(), 1, text.size(), stdout);
  } else if (!WriteFileAtomically(out_path, text, &error.message)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return kExitLocalFile;
  }
  return kExitOk;
}

int RunFlatten(const Connection& c, const std::string& surface_file, const std::string& svg_path,
               bool json_output) {
  json request;
  CliError error;
  std::string mesh;
  if (!ReadSurfaceRequest(surface_file, &request, &error, &mesh)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return kExitLocalFile;  // the surface file is the one input: unreadable or unusable
  }
  proto::CreateSurfaceRequest parsed;
  if (!ReadRequest(request, proto::ParseCreateSurfaceRequest, &parsed, &error)) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", surface_file.c_str(), error.message.c_str());
    return error.exit_code();
  }
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  HttpReply r;
  HttpFailure f;
  if (!mesh.empty() && !client.PostModel(mesh, proto::Sha256Hex(mesh, 32), &r, &f)) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", surface_file.c_str(), f.message.c_str());
    return ExitFor(f);
  }
  if (!client.PostJson("/v1/surfaces", proto::ToJson(parsed).dump(), &r, &f)) {
    std::fprintf(stderr, "surfdeform: %s\n", f.message.c_str());
    return ExitFor(f);
  }
  json j;
  if (!ReplyWithId(r, &j)) return kExitUnavailable;
  if (json_output) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    const json& q = j["quality"];
    std::printf("id %s%s\n", j["id"].get<std::string>().c_str(),
                j.value("cached", false) ? " (cached)" : "");
    std::printf("grid %dx%d, method %s, %.1f ms\n", j["grid"].value("nu", 0),
                j["grid"].value("nv", 0), j.value("method", "").c_str(),
                j["timing_ms"].value("flatten", 0.0));
    std::printf("stress %.4g, max edge error %.4g, area ratio %.4g..%.4g, folded cells %d\n",
                q.value("stress", 0.0), q.value("max_edge_error", 0.0),
                q.value("area_ratio_min", 0.0), q.value("area_ratio_max", 0.0),
                q.value("folded_cells", 0));
  }
  if (!svg_path.empty()) {
    HttpReply svg;
    if (!client.Get("/v1/surfaces/" + j["id"].get<std::string>() + "/flat.svg", &svg, &f)) {
      std::fprintf(stderr, "surfdeform: %s\n", f.message.c_str());
      return ExitFor(f);
    }
    if (!WriteFileAtomically(svg_path, svg.body, &error.message)) {
      std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
      return kExitLocalFile;
    }
  }
  return kExitOk;
}

namespace {

// --params, a JSON object (empty without it).
bool ReadParams(const DeformOptions& o, json* params, CliError* error) {
  *params = json::object();
  if (o.params.empty()) return true;
  if (!ReadJsonArgument(o.params, params, error)) return false;
  if (!params->is_object()) {
    *error = {CliError::Kind::kUsage, "--params: a JSON object is needed"};
    return false;
  }
  return true;
}

// The request from `params` (--params with the surface's or the
// animation's parts in place) and the flags.
bool FinishDeformRequest(const json& params, const DeformOptions& o, OutputKind kind,
                         DeformRequest* out, CliError* error) {
  if (!ReadRequest(params, proto::ParseDeformParams, &out->params, error) ||
      !ApplyFlags(o, kind, &out->params, &out->decode, error) ||
      !CheckAsSent(out->params, proto::ParseDeformParams, error)) {
    return false;
  }
  out->kind = kind;
  switch (kind) {
    case OutputKind::kDrc:
      out->accept = "application/octet-stream";
      break;
    case OutputKind::kGlb:
      out->accept = "model/gltf-binary";
      break;
    case OutputKind::kObj:
    case OutputKind::kPly:
      out->accept = "";
      break;
  }
  return true;
}

// --params with the animation file's parts in place.
bool ReadAnimationParams(const DeformOptions& o, const json& animation, json* params,
                         CliError* error) {
  if (!ReadParams(o, params, error)) return false;
  for (const char* key : {"animation", "sampling", "flatten"}) {
    if (animation.contains(key)) (*params)[key] = animation[key];
  }
  return true;
}

}  // namespace

bool BuildDeformRequest(const DeformOptions& o, OutputKind kind, DeformRequest* out,
                        CliError* error) {
  json params;
  if (!ReadParams(o, &params, error)) return false;
  if (!o.surface_file.empty()) {
    json request;
    if (!ReadSurfaceRequest(o.surface_file, &request, error, &out->surface_mesh)) return false;
    params.erase("surface_id");
    for (const char* key : {"surface", "sampling", "flatten"}) {
      if (request.contains(key)) params[key] = request[key];
    }
  }
  if (!o.surface_id.empty()) {
    for (const char* key : {"surface", "sampling", "flatten"}) params.erase(key);
    params["surface_id"] = o.surface_id;
  }
  if (!params.contains("surface") && !params.contains("surface_id") &&
      !params.contains("animation")) {
    *error = {CliError::Kind::kUsage,
              "no surface: give --surface FILE, --surface-id ID, or a surface in --params"};
    return false;
  }
  return FinishDeformRequest(params, o, kind, out, error);
}

bool BuildFrameRequest(const DeformOptions& o, const json& animation, OutputKind kind,
                       DeformRequest* out, CliError* error) {
  json params;
  if (!ReadAnimationParams(o, animation, &params, error)) return false;
  params["frame"] = 0;
  return FinishDeformRequest(params, o, kind, out, error);
}

bool BuildAnimateRequest(const DeformOptions& o, const json& animation,
                         const std::string& compression, proto::AnimateParams* out,
                         CliError* error) {
  json params;
  if (!ReadAnimationParams(o, animation, &params, error)) return false;
  bool decode = false;
  if (!ReadRequest(params, proto::ParseAnimateParams, out, error) ||
      !ApplyFlags(o, OutputKind::kGlb, out, &decode, error)) {
    return false;
  }
  out->output.format.reset();  // always a GLB: its compression says which
  if (!compression.empty()) {
    proto::GlbCompression c;
    if (!ReadCompression(compression, "meshopt or none", &c, error)) return false;
    out->output.compression = c;
  }
  return CheckAsSent(*out, proto::ParseAnimateParams, error);
}

bool UploadSurfaceMesh(ApiClient& client, const DeformRequest& request, HttpFailure* failure) {
  if (request.surface_mesh.empty()) return true;
  HttpReply uploaded;
  return client.PostModel(request.surface_mesh, proto::Sha256Hex(request.surface_mesh, 32),
                          &uploaded, failure);
}

namespace {

template <typename Params>
bool PostParamsWithModel(ApiClient& client, const std::string& path, const std::string& mesh,
                         Params params, const std::string& accept, HttpReply* out,
                         HttpFailure* failure) {
  params.model_id = proto::ModelId(mesh);  // what the server names it
  const std::string body = proto::ToJson(params).dump();
  if (client.PostJson(path, body, out, failure, accept)) return true;
  if (failure->code != "unknown_model") return false;
  HttpReply uploaded;
  if (!client.PostModel(mesh, params.model_id, &uploaded, failure)) return false;
  return client.PostJson(path, body, out, failure, accept);
}

}  // namespace

bool PostWithModel(ApiClient& client, const std::string& path, const std::string& mesh,
                   proto::DeformParams params, const std::string& accept, HttpReply* out,
                   HttpFailure* failure) {
  return PostParamsWithModel(client, path, mesh, std::move(params), accept, out, failure);
}

bool PostWithModel(ApiClient& client, const std::string& path, const std::string& mesh,
                   proto::AnimateParams params, const std::string& accept, HttpReply* out,
                   HttpFailure* failure) {
  return PostParamsWithModel(client, path, mesh, std::move(params), accept, out, failure);
}

int RunUpload(const Connection& c, const std::string& mesh_path, bool json_output) {
  std::string mesh, message;
  if (!ReadFileBytes(mesh_path, &mesh, &message)) {
    std::fprintf(stderr, "surfdeform: %s\n", message.c_str());
    return kExitLocalFile;
  }
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  HttpReply r;
  HttpFailure f;
  if (!client.PostModel(mesh, proto::Sha256Hex(mesh, 32), &r, &f)) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", mesh_path.c_str(), f.message.c_str());
    return ExitFor(f);
  }
  json j;
  if (!ReplyWithId(r, &j)) return kExitUnavailable;
  if (json_output) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%s\n", j["id"].get<std::string>().c_str());
    std::fprintf(stderr, "%s: %s, %d vertices, %d triangles, up %s (%s)\n", mesh_path.c_str(),
                 j.value("format", "").c_str(), j.value("vertices", 0), j.value("triangles", 0),
                 j.value("up", "").c_str(), r.status == 201 ? "uploaded" : "already on the server");
  }
  return kExitOk;
}

int DeformFile(ApiClient& client, const DeformRequest& request, const std::string& mesh_path,
               const std::string& out_path, std::string* message) {
  HttpReply r;
  HttpFailure f;
  bool sent = false;
  if (!UploadSurfaceMesh(client, request, &f)) {
    *message = f.message;
    return ExitFor(f);
  }
  if (mesh_path.empty()) {
    sent =
        client.PostJson("/v1/deform", proto::ToJson(request.params).dump(), &r, &f, request.accept);
  } else {
    std::string mesh;
    if (!ReadFileBytes(mesh_path, &mesh, message)) return kExitLocalFile;
    sent = PostWithModel(client, "/v1/deform", mesh, request.params, request.accept, &r, &f);
  }
  if (!sent) {
    *message = f.message;
    return ExitFor(f);
  }
  std::string bytes = std::move(r.body);
  if (request.decode) {
    std::string decoded;
    if (!DracoTo(bytes, request.kind, &decoded, message)) return kExitLocalFile;
    bytes = std::move(decoded);
  }
  if (!WriteFileAtomically(out_path, bytes, message)) return kExitLocalFile;
  const json stats = json::parse(r.stats, nullptr, false);
  if (!stats.is_discarded() && stats.is_object()) {
    const json sub = stats.value("subdivision", json::object());
    *message = std::to_string(stats.value("vertices", 0)) + " vertices, " +
               std::to_string(stats.value("triangles", 0)) + " triangles" +
               (sub.value("vertices_added", 0) > 0
                    ? " (" + std::to_string(sub.value("vertices_added", 0)) + " added)"
                    : "") +
               ", " + std::to_string(bytes.size()) + " bytes";
    if (const json d = stats.value("distortion", json()); d.is_object()) {
      char line[128];
      std::snprintf(line, sizeof line, "; distortion max %.4g, p95 %.4g, mean %.4g",
                    d.value("max", 0.0), d.value("p95", 0.0), d.value("mean", 0.0));
      *message += line;
    }
  }
  return kExitOk;
}

int RunDeform(const Connection& c, const DeformOptions& o, const std::string& mesh_path,
              const std::string& out_path) {
  const auto kind = OutputKindOf(out_path);
  if (!kind) {
    std::fprintf(stderr,
                 "surfdeform: %s: the output's extension picks the format: .drc, .glb, "
                 ".obj or .ply\n",
                 out_path.c_str());
    return kExitUsage;
  }
  DeformRequest request;
  CliError error;
  if (!BuildDeformRequest(o, *kind, &request, &error)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return error.exit_code();
  }
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  std::string message;
  const std::string what = !mesh_path.empty() ? mesh_path
                           : !o.text.empty()  ? "text \"" + o.text + "\""
                                              : "model " + o.model_id;
  const int code = DeformFile(client, request, mesh_path, out_path, &message);
  if (code != kExitOk) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", what.c_str(), message.c_str());
    return code;
  }
  std::printf("%s -> %s: %s\n", what.c_str(), out_path.c_str(), message.c_str());
  return kExitOk;
}

}  // namespace surfdeform::cli
