// surfdeform: the command-line client of a surfdeform server, for batch jobs.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <thread>

#include "cli/commands.hpp"
#include "cli/usage_errors.hpp"
#include "engine/subdivision/subdivision_mode.hpp"

namespace {

constexpr char kExitCodes[] = R"(Exit codes:
  0  success
  1  usage: bad flags or arguments
  2  the request is refused (its message is printed): fix the request. By the server (4xx),
     or here, before it is sent, by the API's own request types (unknown fields, types, ranges)
  3  the server could not be reached or failed (5xx), after retrying what is safe to retry
     (connection errors, 503 with Retry-After); 4xx are never retried
  4  a local file could not be read, written or decoded
  5  batch: some files failed (each is reported with the server's message); the rest are done
Server: --server URL or SURFDEFORM_SERVER (default http://127.0.0.1:8080).
The global options (--server, --retries, --timeout, -v) go before or after the subcommand.)";

using namespace surfdeform::cli;

// Every subcommand's arguments, filled by the parse.
struct Arguments {
  Connection connection;
  DeformOptions deform;  // deform, batch and animate
  AnimateOptions animate;
  std::string surface_file, svg_path;  // flatten
  bool json_output = false;
  std::string map_id, map_request, map_out;  // map
  std::string mesh_path, out_path;           // deform
  std::string upload_path;                   // upload
  bool upload_json = false;
  std::vector<std::string> inputs;  // batch
  std::string texts_path;           // batch --texts
  std::string out_dir, extension = ".glb";
  int jobs = static_cast<int>(std::max(2u, std::thread::hardware_concurrency()));
  bool force = false;
  std::string animate_mesh, animate_out;  // animate
  PartOptions part;                       // part
  std::string part_out;
};

// The subcommands whose arguments the run reads.
struct Subcommands {
  CLI::App* flatten;
  CLI::App* map;
  CLI::App* deform;
  CLI::App* upload;
  CLI::App* batch;
  CLI::App* animate;
  CLI::App* part;
};

void AddConnectionOptions(CLI::App& app, Connection& c) {
  app.add_option("--server", c.server, "Server URL")
      ->envname("SURFDEFORM_SERVER")
      ->capture_default_str();
  app.add_option("--retries", c.retry.attempts,
                 "Attempts in all for connection errors and 503 (with backoff)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--timeout", c.timeout_s, "Seconds to wait for one reply")
      ->check(CLI::Range(1.0, 86400.0))
      ->capture_default_str();
  app.add_flag("-v,--verbose", c.verbose, "Report retries on stderr");
}

CLI::App* AddFlatten(CLI::App& app, Arguments& x) {
  auto* flatten = app.add_subcommand(
      "flatten", "Flatten a surface: print its id and quality; optionally save the flat sheet");
  flatten
      ->add_option("surface", x.surface_file,
                   "JSON file: a surface request {surface, sampling, flatten} or a bare surface "
                   "{kind, ...}; or a mesh file (.obj .ply .stl .off .glb .gltf .drc): a "
                   "surface given as a mesh, uploaded first")
      ->required();
  flatten->add_option("--svg", x.svg_path, "Save the flat sheet, coloured by stretch, as SVG");
  flatten->add_flag("--json", x.json_output, "Print the server's JSON reply");
  return flatten;
}

CLI::App* AddMap(CLI::App& app, Arguments& x) {
  auto* map = app.add_subcommand(
      "map",
      "Carry marks between a flat sheet and its surface: points or polylines on the "
      "sheet onto the surface, or points in space to the nearest surface points");
  map->add_option("surface-id", x.map_id, "A surface already flattened (see flatten)")->required();
  map->add_option("request", x.map_request,
                  "JSON text or file: {\"points\": [[x, y], ...]}, {\"polylines\": [[[x, y], "
                  "...], ...], \"tolerance\": t, \"max_segment\": s} or {\"surface_points\": "
                  "[[x, y, z], ...]}")
      ->required();
  map->add_option("-o,--output", x.map_out, "Write the reply's JSON here (default: stdout)");
  return map;
}

void AddSubdivisionOptions(CLI::App* sub, DeformOptions& d) {
  sub->add_option("--subdivision", d.subdivision, "subdivision.mode")
      ->check(CLI::IsMember(
          surfdeform::NamesOf<surfdeform::SubdivisionMode>(surfdeform::kSubdivisionModes)));
  sub->add_option("--tolerance", d.tolerance, "subdivision.tolerance, surface units")
      ->check(CLI::PositiveNumber);
}

// The options deform and batch share.
void AddDeformOptions(CLI::App* sub, DeformOptions& d) {
  sub->add_option("--font", d.font,
                  "A text's font (--text, --texts): GET /v1/fonts lists them (or an uploaded "
                  "font's id)");
  sub->add_option("--size-mm", d.size_mm, "A text's em, mm")->check(CLI::PositiveNumber);
  sub->add_option("--depth-mm", d.depth_mm, "A text's depth, mm (0: flat letters)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--surface", d.surface_file,
                  "JSON file: a surface request {surface, sampling, flatten} or a bare surface; "
                  "or a mesh file: a surface given as a mesh (a disk), uploaded first");
  sub->add_option("--surface-id", d.surface_id, "A surface already flattened (see flatten)");
  sub->add_option("--params", d.params,
                  "The deform parameters (placement, subdivision, output.draco ...): JSON text "
                  "or a file");
  sub->add_option("--scale", d.scale, "placement.scale: \"fit\" or a number");
  AddSubdivisionOptions(sub, d);
  sub->add_flag("--distortion", d.distortion,
                "Add the distortion map (.glb: attribute _DISTORTION; .ply: properties "
                "distortion_max, distortion_min) and print its summary");
  sub->add_option("--compression", d.compression,
                  "output.compression for .glb: draco (the default), meshopt (some 10x faster "
                  "for the server to encode; three.js decodes it with MeshoptDecoder) or none")
      ->check(CLI::IsMember({"draco", "meshopt", "none"}));
  sub->add_flag("--lossless", d.lossless,
                "For .obj/.ply, ask the server for them instead of Draco decoded here "
                "(more bytes over the wire, no quantization)");
}

CLI::App* AddDeform(CLI::App& app, Arguments& x) {
  auto* deform = app.add_subcommand(
      "deform", "Deform one mesh; the output's extension (.drc .glb .obj .ply) picks its format");
  // Mesh files are checked when read: one that cannot be is exit code 4, not 1.
  auto* mesh = deform->add_option(
      "mesh", x.mesh_path,
      "Mesh file (glTF/GLB, Draco, OBJ, PLY, STL, OFF); sent once per server (by id after)");
  auto* model_id =
      deform->add_option("--model-id", x.deform.model_id, "A model already uploaded (see upload)")
          ->excludes(mesh);
  deform
      ->add_option("--text", x.deform.text,
                   "A text as the model (\"\\n\" starts a line): shaped and meshed by the "
                   "server, in mm (--font, --size-mm, --depth-mm)")
      ->excludes(mesh)
      ->excludes(model_id);
  deform->add_option("-o,--output", x.out_path, "Output file")->required();
  AddDeformOptions(deform, x.deform);
  return deform;
}

CLI::App* AddPart(CLI::App& app, Arguments& x) {
  auto* part = app.add_subcommand(
      "part",
      "Make a printable part (POST /v1/parts): the surface thickened into a closed solid, in "
      "mm; the output's extension (.3mf .stl .glb .obj .ply .drc) picks its format");
  PartOptions& p = x.part;
  auto* file = part->add_option(
      "surface", p.surface_file,
      "JSON file: a surface request or a bare surface {kind, ...}; its units are mm");
  part->add_option("--surface-id", p.surface_id, "A surface already flattened (see flatten)")
      ->excludes(file);
  part->add_option("--thickness-mm", p.thickness_mm, "body.thickness_mm")
      ->required()
      ->check(CLI::PositiveNumber);
  part->add_option("--side", p.side, "body.side: where the material lies against the normal")
      ->check(CLI::IsMember(surfdeform::NamesOf<surfdeform::BodySide>(surfdeform::kBodySides)))
      ->capture_default_str();
  part->add_option("--samples", p.samples,
                   "The body's samples per side (default: as the surface bends)")
      ->check(CLI::Range(2, 512));
  part->add_option("--min-wall-mm", p.min_wall_mm,
                   "printer.min_wall_mm: a thinner wall is a warning")
      ->check(CLI::NonNegativeNumber);
  part->add_flag("--strict", p.strict, "A wall under --min-wall-mm is an error, not a warning");
  part->add_flag("--report", p.report, "Write the part's report (JSON) instead of the part");
  part->add_option("-o,--output", x.part_out, "Output file")->required();
  return part;
}

CLI::App* AddUpload(CLI::App& app, Arguments& x) {
  auto* upload = app.add_subcommand(
      "upload", "Upload a mesh once (POST /v1/models) and print its id, for deform --model-id");
  upload->add_option("mesh", x.upload_path, "Mesh file (glTF/GLB, Draco, OBJ, PLY, STL, OFF)")
      ->required();
  upload->add_flag("--json", x.upload_json, "Print the server's JSON reply");
  return upload;
}

CLI::App* AddBatch(CLI::App& app, Arguments& x) {
  auto* batch = app.add_subcommand(
      "batch", "Deform many meshes with one set of parameters into a folder (resumable)");
  auto* inputs = batch->add_option("inputs", x.inputs, "Mesh files and folders (their mesh files)");
  batch
      ->add_option("--texts", x.texts_path,
                   "A text file: each non-empty line a text to deform (a name per part), "
                   "written as NNN-the-text.EXT")
      ->excludes(inputs);
  batch->add_option("-o,--output-dir", x.out_dir, "Output folder (created)")->required();
  batch->add_option("--ext", x.extension, "Output format: .drc .glb .obj .ply")
      ->capture_default_str();
  batch->add_option("-j,--jobs", x.jobs, "Requests at once")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  batch->add_flag("--force", x.force, "Redo files whose output exists (default: skip them)");
  AddDeformOptions(batch, x.deform);
  return batch;
}

CLI::App* AddAnimate(CLI::App& app, Arguments& x) {
  auto* animate = app.add_subcommand(
      "animate",
      "Deform one mesh along an animated surface: one .glb that plays every frame (morph "
      "targets), and/or each frame alone into a folder");
  AnimateOptions& a = x.animate;
  animate->add_option("mesh", x.animate_mesh, "Mesh file (glTF/GLB, Draco, OBJ, PLY, STL, OFF)")
      ->required();
  animate->add_option("-o,--output", x.animate_out, "Output .glb");
  animate
      ->add_option("--surface", a.animation_file,
                   "JSON file: {\"animation\": {\"keyframes\": ...}, \"sampling\", "
                   "\"flatten\"} or a bare animation {\"keyframes\": ...}; a keyframe's "
                   "surface may be a mesh file's name (uploaded; all one mesh moving)")
      ->required();
  animate->add_option("--compression", a.compression, "output.compression")
      ->check(CLI::IsMember({"meshopt", "none"}));
  animate->add_option("--frames-dir", a.frames_dir,
                      "Also write each frame alone here (frame_0000.glb ...), with progress");
  animate->add_option("--frame-ext", a.frame_ext, "The frames' format: .drc .glb .obj .ply")
      ->capture_default_str();
  animate->add_option("--params", x.deform.params,
                      "Other parameters (placement, subdivision): JSON text or a file");
  animate->add_option("--scale", x.deform.scale, "placement.scale: \"fit\" or a number");
  AddSubdivisionOptions(animate, x.deform);
  return animate;
}

// The subcommand given, run with its arguments.
int Run(const CLI::App& app, const Subcommands& s, const Arguments& x) {
  const Connection& c = x.connection;
  if (app.got_subcommand("info")) return RunInfo(c);
  if (app.got_subcommand("health")) return RunHealth(c);
  if (s.flatten->parsed()) return RunFlatten(c, x.surface_file, x.svg_path, x.json_output);
  if (s.map->parsed()) return RunMap(c, x.map_id, x.map_request, x.map_out);
  if (s.deform->parsed()) {
    const int models = !x.mesh_path.empty() + !x.deform.model_id.empty() + !x.deform.text.empty();
    if (models != 1) {
      std::fprintf(stderr, "surfdeform deform: give a mesh file, --model-id ID or --text TEXT\n");
      return kExitUsage;
    }
    return RunDeform(c, x.deform, x.mesh_path, x.out_path);
  }
  if (s.upload->parsed()) return RunUpload(c, x.upload_path, x.upload_json);
  if (s.part->parsed()) return RunPart(c, x.part, x.part_out);
  if (s.animate->parsed()) {
    return RunAnimate(c, x.deform, x.animate, x.animate_mesh, x.animate_out);
  }
  if (s.batch->parsed()) {
    if (x.inputs.empty() == x.texts_path.empty()) {
      std::fprintf(stderr, "surfdeform batch: give mesh files or folders, or --texts FILE\n");
      return kExitUsage;
    }
    if (!x.texts_path.empty()) {
      return RunTextBatch(c, x.deform, x.texts_path, x.out_dir, x.extension, x.jobs, x.force);
    }
    return RunBatch(c, x.deform, x.inputs, x.out_dir, x.extension, x.jobs, x.force);
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"surfdeform: bend 3D models along curved surfaces through a surfdeform server."};
  app.footer(kExitCodes);
  app.require_subcommand(1);
  // Global options also after the subcommand (subcommands inherit this):
  // `surfdeform deform --server URL ...` as well as `surfdeform --server URL deform ...`.
  app.fallthrough(true);
  Arguments x;
  AddConnectionOptions(app, x.connection);
  app.add_subcommand("info", "Print the server's version, limits, formats and surface kinds");
  app.add_subcommand("health", "Check that the server is live and ready (exit 0) or not (3)");
  Subcommands s;
  s.flatten = AddFlatten(app, x);
  s.map = AddMap(app, x);
  s.deform = AddDeform(app, x);
  s.upload = AddUpload(app, x);
  s.batch = AddBatch(app, x);
  s.animate = AddAnimate(app, x);
  s.part = AddPart(app, x);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ExtrasError& e) {
    // CLI11 lists leftovers in reverse and without saying why; name each
    // unknown or misplaced option, and where it belongs.
    const std::string why = ExplainUnexpected(app, argc, argv);
    if (why.empty()) return app.exit(e) == 0 ? kExitOk : kExitUsage;
    std::fprintf(stderr, "%sRun with --help for more information.\n", why.c_str());
    return kExitUsage;
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  return Run(app, s, x);
}
