// surfdeform animate: a model along an animated surface, as one GLB that plays
// every frame (POST /v1/animate), and optionally each frame alone (POST
// /v1/deform with "frame"), with progress on stderr.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/output_files.hpp"
#include "proto/content_hash.hpp"

namespace surfdeform::cli {
namespace {

using nlohmann::json;

// {"animation", "sampling", "flatten"} from the file, or a bare animation.
// A keyframe whose surface is a string names a mesh file (a cloth
// simulation's frame; relative to the animation file's folder): its bytes
// go to *meshes and the key becomes {"kind": "mesh", "model_id": <its id>}.
bool ReadAnimation(const std::string& file, json* out, std::vector<std::string>* meshes,
                   CliError* error) {
  json j;
  if (!ReadJsonArgument(file, &j, error)) return false;
  if (!j.is_object() || (!j.contains("animation") && !j.contains("keyframes"))) {
    *error = {CliError::Kind::kUsage,
              file +
                  ": an animation file holds {\"animation\": {\"keyframes\": ...}, ...} or "
                  "{\"keyframes\": ...}"};
    return false;
  }
  *out = j.contains("animation") ? j : json{{"animation", j}};
  json& keys = (*out)["animation"]["keyframes"];
  if (!keys.is_array()) return true;  // the server says what is wrong
  // Relative to the animation file's folder; for JSON given inline, to here.
  const size_t first = file.find_first_not_of(" \t\r\n");
  const bool inline_json = first != std::string::npos && (file[first] == '{' || file[first] == '[');
  const std::filesystem::path folder =
      inline_json ? std::filesystem::path() : std::filesystem::path(file).parent_path();
  for (json& key : keys) {
    if (!key.is_object() || !key.contains("surface") || !key["surface"].is_string()) continue;
    const std::filesystem::path named = key["surface"].get<std::string>();
    const std::string path = (named.is_relative() ? folder / named : named).string();
    std::string bytes;
    if (!ReadFileBytes(path, &bytes, &error->message)) {
      error->kind = CliError::Kind::kLocalFile;
      return false;
    }
    key["surface"] = {{"kind", "mesh"}, {"model_id", proto::Sha256Hex(bytes, 32)}};
    meshes->push_back(std::move(bytes));
  }
  return true;
}

// "parse 1.2 ms, flatten 30.1 ms, ..." from a Server-Timing header.
std::string Timings(const std::string& header) {
  std::string out;
  size_t at = 0;
  while (at < header.size()) {
    size_t end = header.find(',', at);
    if (end == std::string::npos) end = header.size();
    std::string item = header.substr(at, end - at);
    item.erase(0, item.find_first_not_of(' '));
    const size_t semi = item.find(";dur=");
    if (semi != std::string::npos) {
      out += (out.empty() ? "" : ", ") + item.substr(0, semi) + " " + item.substr(semi + 5) + " ms";
    }
    at = end + 1;
  }
  return out;
}

}  // namespace

int RunAnimate(const Connection& c, const DeformOptions& d, const AnimateOptions& a,
               const std::string& mesh_path, const std::string& out_path) {
  if (out_path.empty() && a.frames_dir.empty()) {
    std::fprintf(stderr, "surfdeform: give -o FILE.glb, --frames-dir DIR, or both\n");
    return kExitUsage;
  }
  if (!out_path.empty() && OutputKindOf(out_path) != OutputKind::kGlb) {
    std::fprintf(stderr, "surfdeform: %s: an animation is a GLB (.glb)\n", out_path.c_str());
    return kExitUsage;
  }
  const auto frame_kind = OutputKindOf("frame" + a.frame_ext);
  if (!frame_kind) {
    std::fprintf(stderr, "surfdeform: --frame-ext: .drc, .glb, .obj or .ply, got %s\n",
                 a.frame_ext.c_str());
    return kExitUsage;
  }
  CliError error;
  json animation;
  std::vector<std::string> key_meshes;
  if (!ReadAnimation(a.animation_file, &animation, &key_meshes, &error)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return error.exit_code();
  }
  // The deform options' parameters (placement, subdivision, --scale ...),
  // with the animation in place of a surface.
  // With --frames, each frame alone: the animation's request with a frame,
  // as POST /v1/deform takes it. Both read before anything is sent.
  proto::AnimateParams params;
  DeformRequest frame_request;
  if ((!out_path.empty() && !BuildAnimateRequest(d, animation, a.compression, &params, &error)) ||
      (!a.frames_dir.empty() &&
       !BuildFrameRequest(d, animation, *frame_kind, &frame_request, &error))) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return error.exit_code();
  }
  const int frames = out_path.empty() ? frame_request.params.animation->animation.frames
                                      : params.animation.animation.frames;
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  // The keyframes' meshes, uploaded once (the server keeps what it knew).
  std::set<std::string> uploaded;
  for (const std::string& mesh : key_meshes) {
    const std::string id = proto::Sha256Hex(mesh, 32);
    if (!uploaded.insert(id).second) continue;
    HttpReply r;
    HttpFailure f;
    if (!client.PostModel(mesh, id, &r, &f)) {
      std::fprintf(stderr, "surfdeform: a keyframe's mesh: %s\n", f.message.c_str());
      return ExitFor(f);
    }
  }

  if (!out_path.empty()) {
    std::string mesh, message;
    if (!ReadFileBytes(mesh_path, &mesh, &message)) {
      std::fprintf(stderr, "surfdeform: %s\n", message.c_str());
      return kExitLocalFile;
    }
    std::fprintf(stderr, "animating %d frames of %s ...\n", frames, mesh_path.c_str());
    HttpReply r;
    HttpFailure f;
    if (!PostWithModel(client, "/v1/animate", mesh, params, "model/gltf-binary", &r, &f)) {
      std::fprintf(stderr, "surfdeform: %s: %s\n", mesh_path.c_str(), f.message.c_str());
      return ExitFor(f);
    }
    if (!WriteFileAtomically(out_path, r.body, &message)) {
      std::fprintf(stderr, "surfdeform: %s\n", message.c_str());
      return kExitLocalFile;
    }
    const json stats = json::parse(r.stats, nullptr, false);
    std::printf("%s -> %s: %d frames at %g fps, %d vertices, %zu bytes (%s)\n", mesh_path.c_str(),
                out_path.c_str(), stats.is_object() ? stats.value("frames", frames) : frames,
                stats.is_object() ? stats.value("fps", 0.0) : 0.0,
                stats.is_object() ? stats.value("vertices", 0) : 0, r.body.size(),
                Timings(r.timing).c_str());
  }

  if (!a.frames_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.frames_dir, ec);
    if (ec) {
      std::fprintf(stderr, "surfdeform: %s: %s\n", a.frames_dir.c_str(), ec.message().c_str());
      return kExitLocalFile;
    }
    const bool tty = isatty(fileno(stderr)) != 0;  // a line per frame in logs
    for (int k = 0; k < frames; ++k) {
      frame_request.params.frame = k;
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d", k);
      const std::string path = a.frames_dir + "/" + name + a.frame_ext;
      std::string message;
      const int code = DeformFile(client, frame_request, mesh_path, path, &message);
      if (code != kExitOk) {
        std::fprintf(stderr, "\nsurfdeform: frame %d: %s\n", k, message.c_str());
        return code;
      }
      std::fprintf(stderr, "%sframe %d/%d -> %s%s", tty ? "\r" : "", k + 1, frames, path.c_str(),
                   tty ? "" : "\n");
    }
    if (tty) std::fprintf(stderr, "\n");
    std::printf("%d frames -> %s/\n", frames, a.frames_dir.c_str());
  }
  return kExitOk;
}

}  // namespace surfdeform::cli
