#include "cli/commands.hpp"

#include <cctype>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "proto/content_hash.hpp"

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

namespace {

// Whether `file` is named as a mesh file (a surface given as a mesh).
bool IsMeshFile(const std::string& file) {
  const auto dot = file.rfind('.');
  if (dot == std::string::npos) return false;
  std::string ext = file.substr(dot);
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  for (const char* e : {".obj", ".ply", ".stl", ".off", ".glb", ".gltf", ".drc"}) {
    if (ext == e) return true;
  }
  return false;
}

// {"surface": ..., "sampling": ..., "flatten": ...} from a surface file: a
// whole surface request, a bare surface ({"kind": ...}), or a mesh file,
// which is the surface {"kind": "mesh", "model_id": <its id>} (its bytes to
// `mesh`, for the caller to upload).
bool ReadSurfaceRequest(const std::string& file, json* out, CliError* error,
                        std::string* mesh = nullptr) {
  if (IsMeshFile(file) && mesh != nullptr) {
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
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  HttpReply r;
  HttpFailure f;
  if (!client.PostJson("/v1/surfaces/" + surface_id + "/map", body.dump(), &r, &f)) {
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
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  HttpReply r;
  HttpFailure f;
  if (!mesh.empty() && !client.PostModel(mesh, proto::Sha256Hex(mesh, 32), &r, &f)) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", surface_file.c_str(), f.message.c_str());
    return ExitFor(f);
  }
  if (!client.PostJson("/v1/surfaces", request.dump(), &r, &f)) {
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

bool BuildDeformRequest(const DeformOptions& o, OutputKind kind, DeformRequest* out,
                        CliError* error) {
  json params = json::object();
  if (!o.params.empty()) {
    if (!ReadJsonArgument(o.params, &params, error)) return false;
    if (!params.is_object()) {
      *error = {CliError::Kind::kUsage, "--params: a JSON object is needed"};
      return false;
    }
  }
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
  if (!o.model_id.empty()) params["model_id"] = o.model_id;
  if (!o.subdivision.empty()) params["subdivision"]["mode"] = o.subdivision;
  if (o.tolerance > 0.0) params["subdivision"]["tolerance"] = o.tolerance;
  if (!o.scale.empty()) {
    if (o.scale == "fit") {
      params["placement"]["scale"] = "fit";
    } else {
      char* end = nullptr;
      const double s = std::strtod(o.scale.c_str(), &end);
      if (end == o.scale.c_str() || *end != '\0') {
        *error = {CliError::Kind::kUsage, "--scale: \"fit\" or a number, got " + o.scale};
        return false;
      }
      params["placement"]["scale"] = s;
    }
  }
  out->kind = kind;
  out->decode = false;
  json& output = params["output"];
  const bool distortion = o.distortion || (output.is_object() && output.value("distortion", false));
  if (distortion) {
    if (kind != OutputKind::kGlb && kind != OutputKind::kPly) {
      *error = {CliError::Kind::kUsage,
                "--distortion: the distortion map is written in .glb and .ply output only"};
      return false;
    }
    output["distortion"] = true;
  }
  if (!o.compression.empty()) {
    if (kind != OutputKind::kGlb) {
      *error = {CliError::Kind::kUsage, "--compression: compresses .glb output only"};
      return false;
    }
    output["compression"] = o.compression;
  }
  switch (kind) {
    case OutputKind::kDrc:
      output["format"] = "drc";
      out->accept = "application/octet-stream";
      break;
    case OutputKind::kGlb:
      output["format"] = "glb";
      out->accept = "model/gltf-binary";
      break;
    case OutputKind::kObj:
    case OutputKind::kPly:
      if (o.lossless || distortion) {  // Draco would not carry the distortion map
        output["format"] = kind == OutputKind::kObj ? "obj" : "ply";
      } else {
        // Draco over the wire (a fraction of the bytes), decoded here; the
        // sequential encoding keeps the vertex order.
        output["format"] = "drc";
        output["draco"]["sequential"] = true;
        out->decode = true;
      }
      out->accept = "";
      break;
  }
  out->params = params.dump();
  return true;
}

bool UploadSurfaceMesh(ApiClient& client, const DeformRequest& request, HttpFailure* failure) {
  if (request.surface_mesh.empty()) return true;
  HttpReply uploaded;
  return client.PostModel(request.surface_mesh, proto::Sha256Hex(request.surface_mesh, 32),
                          &uploaded, failure);
}

bool PostWithModel(ApiClient& client, const std::string& path, const std::string& mesh,
                   const std::string& params, const std::string& accept, HttpReply* out,
                   HttpFailure* failure) {
  json p = json::parse(params);
  const std::string id = proto::Sha256Hex(mesh, 32);  // what the server names it (proto/api.hpp)
  p["model_id"] = id;
  const std::string body = p.dump();
  if (client.PostJson(path, body, out, failure, accept)) return true;
  if (failure->code != "unknown_model") return false;
  HttpReply uploaded;
  if (!client.PostModel(mesh, id, &uploaded, failure)) return false;
  return client.PostJson(path, body, out, failure, accept);
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
    sent = client.PostJson("/v1/deform", request.params, &r, &f, request.accept);
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
  const std::string what = mesh_path.empty() ? "model " + o.model_id : mesh_path;
  const int code = DeformFile(client, request, mesh_path, out_path, &message);
  if (code != kExitOk) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", what.c_str(), message.c_str());
    return code;
  }
  std::printf("%s -> %s: %s\n", what.c_str(), out_path.c_str(), message.c_str());
  return kExitOk;
}

}  // namespace surfdeform::cli
