// The subcommands of the `surfdeform` command-line client. Each returns the
// process exit code (see ExitCode) and prints what a person needs: results on
// stdout, progress and errors on stderr.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/api_client.hpp"
#include "cli/output_files.hpp"
#include "proto/api.hpp"

namespace surfdeform::cli {

// Documented in `surfdeform --help` and docs/cli.md.
enum ExitCode {
  kExitOk = 0,
  kExitUsage = 1,        // bad flags or arguments
  kExitRefused = 2,      // the server refused the request (4xx): fix the request
  kExitUnavailable = 3,  // the server could not be reached or failed (5xx), after retries
  kExitLocalFile = 4,    // an input could not be read or an output written or decoded
  kExitPartial = 5,      // batch: some files failed, the others are done
};

// A failure before any request is sent: which kind it is (and so the exit
// code), and the message for the person.
// kRefused: a request the API's own parsers (proto) refuse, as the server
// would, with the same message; it is not sent.
struct CliError {
  enum class Kind { kUsage, kLocalFile, kRefused };
  Kind kind = Kind::kUsage;
  std::string message;
  int exit_code() const {
    switch (kind) {
      case Kind::kLocalFile:
        return kExitLocalFile;
      case Kind::kRefused:
        return kExitRefused;
      case Kind::kUsage:
        break;
    }
    return kExitUsage;
  }
};

struct Connection {
  std::string server = "http://127.0.0.1:8080";
  RetryPolicy retry;
  double timeout_s = 300.0;
  bool verbose = false;  // report retries
};

// What a deformation asks for: the surface, inline (a file holding an API
// surface request, or just its "surface" object) or by id, and the other
// parameters (a JSON object, inline or a file), with a few overrides.
struct DeformOptions {
  std::string model_id;  // a model uploaded before, instead of a mesh file
  // Or a text as the model ("text" of the parameters): the string, and the
  // font, size and depth when given (> 0 / >= 0; else the server's defaults).
  std::string text;
  std::string font;
  double size_mm = 0.0;
  double depth_mm = -1.0;
  std::string surface_file;
  std::string surface_id;
  std::string params;       // JSON text, or a file name
  std::string subdivision;  // "off", "adaptive", "uniform" or empty
  double tolerance = 0.0;   // > 0: subdivision.tolerance
  std::string scale;        // "fit" or a number, or empty
  bool lossless = false;    // .obj/.ply: ask for them instead of decoding Draco locally
  bool distortion = false;  // output.distortion (.glb and .ply only; .ply then comes lossless)
  std::string compression;  // output.compression (.glb only): "draco", "meshopt", "none" or empty
};

// POST /v1/surfaces/{id}/map with `request` (JSON text or a file: points,
// polylines or surface_points); the reply's JSON to `out_path`, or stdout.
int RunMap(const Connection& c, const std::string& surface_id, const std::string& request,
           const std::string& out_path);
int RunInfo(const Connection& c);
// POST /v1/models: prints the model's id (and what the server read).
int RunUpload(const Connection& c, const std::string& mesh_path, bool json_output);
int RunHealth(const Connection& c);
int RunFlatten(const Connection& c, const std::string& surface_file, const std::string& svg_path,
               bool json_output);
int RunDeform(const Connection& c, const DeformOptions& o, const std::string& mesh_path,
              const std::string& out_path);
// POST /v1/animate: `animation_file` holds {"animation", "sampling",
// "flatten"} or a bare animation ({"keyframes", ...}); the GLB to out_path
// (may be empty with frames_dir), and with frames_dir each frame alone
// (POST /v1/deform with "frame") as frame_NNNN.<frame_ext>.
struct AnimateOptions {
  std::string animation_file;
  std::string compression;  // "meshopt", "none" or empty
  std::string frames_dir;
  std::string frame_ext = ".glb";
};
int RunAnimate(const Connection& c, const DeformOptions& d, const AnimateOptions& a,
               const std::string& mesh_path, const std::string& out_path);
// batch --texts: each non-empty line of `texts_path` deformed as a text
// ("text" of the parameters) into out_dir/NNN-the-text.EXT, as RunBatch.
int RunTextBatch(const Connection& c, const DeformOptions& o, const std::string& texts_path,
                 const std::string& out_dir, const std::string& extension, int jobs, bool force);
int RunBatch(const Connection& c, const DeformOptions& o, const std::vector<std::string>& inputs,
             const std::string& out_dir, const std::string& extension, int jobs, bool force);

// Shared by the subcommands.
int ExitFor(const HttpFailure& f);
void ConfigureRetries(const Connection& c, ApiClient* client);
// JSON text, or the name of a file holding it.
bool ReadJsonArgument(const std::string& text_or_file, nlohmann::json* out, CliError* error);

// {"surface": ..., "sampling": ..., "flatten": ...} from a surface file: a
// whole surface request, a bare surface ({"kind": ...}), or a mesh file,
// which is the surface {"kind": "mesh", "model_id": <its id>} (its bytes to
// `mesh`, for the caller to upload; without `mesh`, a mesh file is JSON
// that fails to read).
bool ReadSurfaceRequest(const std::string& file, nlohmann::json* out, CliError* error,
                        std::string* mesh = nullptr);

// A request the API refuses: its field and message, as the server gives them.
CliError Refused(const Status& status);

// Reads `request` with `parse` (one of proto's parsers) into *out; false
// with the error when the API refuses it.
template <typename Params, typename Parse>
bool ReadRequest(const nlohmann::json& request, Parse parse, Params* out, CliError* error) {
  auto parsed = parse(request);
  if (!parsed.ok()) {
    *error = Refused(parsed.status());
    return false;
  }
  *out = std::move(*parsed);
  return true;
}

// surfdeform part: a printable part (POST /v1/parts) from a surface file or
// a surface id; the output's extension picks its format (.3mf .stl .glb
// .obj .ply .drc), or --report writes the report's JSON. Prints the report's
// summary and warnings.
struct PartOptions {
  std::string surface_file;
  std::string surface_id;
  double thickness_mm = 0.0;
  std::string side = "outside";
  int samples = 0;  // per side; 0: as the surface bends
  double min_wall_mm = 0.0;
  bool strict = false;
  bool report = false;
};
int RunPart(const Connection& c, const PartOptions& o, const std::string& out_path);

// Shared by deform, batch and animate.
struct DeformRequest {
  proto::DeformParams params;  // sent as proto::ToJson(params)
  // A surface given as a mesh file (--surface panel.obj): its bytes, which
  // the params name by id ({"kind": "mesh", "model_id"}) and which go to the
  // server first (UploadSurfaceMesh); empty otherwise.
  std::string surface_mesh;
  std::string accept;
  OutputKind kind = OutputKind::kDrc;
  bool decode = false;  // the reply is Draco to turn into OBJ/PLY here
};

// Uploads request.surface_mesh (POST /v1/models; a mesh the server holds
// already costs a reply), when there is one.
bool UploadSurfaceMesh(ApiClient& client, const DeformRequest& request, HttpFailure* failure);

// The request for an output of `kind`, from the options: --params (with
// the surface file's parts in place) read by proto's parser, then the flags
// on the request, which is read back once more; false with the error (a
// file that cannot be read, options that make no request, or one the API
// refuses).
bool BuildDeformRequest(const DeformOptions& o, OutputKind kind, DeformRequest* out,
                        CliError* error);

// The same for POST /v1/animate: --params with the animation file's
// {"animation", "sampling", "flatten"} in place, and the flags;
// output.compression is `compression` when not empty.
bool BuildAnimateRequest(const DeformOptions& o, const nlohmann::json& animation,
                         const std::string& compression, proto::AnimateParams* out,
                         CliError* error);

// One frame of that animation alone (POST /v1/deform with "frame": 0; the
// caller sets params.frame), for an output of `kind`.
bool BuildFrameRequest(const DeformOptions& o, const nlohmann::json& animation, OutputKind kind,
                       DeformRequest* out, CliError* error);

// POST `path` with `params` naming the mesh by its id: the mesh is uploaded
// (POST /v1/models) only when the server does not hold it (404
// unknown_model: never sent, or evicted since), and the request sent again.
// So a mesh crosses the wire once per server however many requests use it.
bool PostWithModel(ApiClient& client, const std::string& path, const std::string& mesh,
                   proto::DeformParams params, const std::string& accept, HttpReply* out,
                   HttpFailure* failure);
bool PostWithModel(ApiClient& client, const std::string& path, const std::string& mesh,
                   proto::AnimateParams params, const std::string& accept, HttpReply* out,
                   HttpFailure* failure);

// One mesh through the server into `out_path` (an empty `mesh_path`: the
// model the request's parameters name by id). Returns an exit code; on
// failure *message says why, on success it summarises the result.
int DeformFile(ApiClient& client, const DeformRequest& request, const std::string& mesh_path,
               const std::string& out_path, std::string* message);

}  // namespace surfdeform::cli
