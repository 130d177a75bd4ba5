// surfdeform part: POST /v1/parts from the command line.
#include <cctype>
#include <cstdio>

#include "cli/commands.hpp"

namespace surfdeform::cli {
namespace {

using nlohmann::json;

// The output format a part's file name asks for, by its extension.
std::string FormatOf(const std::string& path) {
  const size_t dot = path.rfind('.');
  if (dot == std::string::npos) return "";
  std::string ext = path.substr(dot + 1);
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  for (const auto& e : proto::kOutputFormats) {
    if (ext == e.name && ext != "glb_plain") return ext;
  }
  return "";
}

// One line of the report for a person, and its warnings.
void PrintReport(const std::string& path, const json& r) {
  if (!r.is_object()) return;
  const json& c = r.value("checks", json::object());
  std::printf(
      "%s: %.6g mm^3, %.6g mm^2, %llu triangles, box %.4g x %.4g x %.4g mm, %s, wall %.4g mm\n",
      path.c_str(), r.value("volume_mm3", 0.0), r.value("area_mm2", 0.0),
      static_cast<unsigned long long>(r.value("triangles", 0ull)),
      r["bounding_box_mm"]["size"][0].get<double>(), r["bounding_box_mm"]["size"][1].get<double>(),
      r["bounding_box_mm"]["size"][2].get<double>(),
      c.value("closed", false) && c.value("oriented", false) && !c.value("self_intersections", true)
          ? "closed and sound"
          : "NOT SOUND",
      r.value("thinnest_wall_mm", 0.0));
  for (const json& w : r.value("warnings", json::array())) {
    std::fprintf(stderr, "surfdeform: warning: %s\n", w.get<std::string>().c_str());
  }
}

}  // namespace

int RunPart(const Connection& c, const PartOptions& o, const std::string& out_path) {
  json request = {{"body", {{"thickness_mm", o.thickness_mm}, {"side", o.side}}}};
  CliError error;
  if (!o.surface_file.empty() == !o.surface_id.empty()) {
    std::fprintf(stderr, "surfdeform part: give a surface file or --surface-id ID\n");
    return kExitUsage;
  }
  if (!o.surface_file.empty()) {
    json surface;
    if (!ReadSurfaceRequest(o.surface_file, &surface, &error)) {
      std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
      return kExitLocalFile;
    }
    request["surface"] = surface["surface"];  // the body's grid is its own
  } else {
    request["surface_id"] = o.surface_id;
  }
  if (o.samples > 0) request["sampling"] = {{"nu", o.samples}, {"nv", o.samples}};
  if (o.min_wall_mm > 0) request["printer"] = {{"min_wall_mm", o.min_wall_mm}};
  if (o.strict) request["strict"] = true;
  if (!o.report) {
    const std::string format = FormatOf(out_path);
    if (format.empty()) {
      std::fprintf(stderr,
                   "surfdeform part: %s: the extension picks the format (.3mf .stl .glb .obj "
                   ".ply .drc)\n",
                   out_path.c_str());
      return kExitUsage;
    }
    request["output"] = {{"format", format}};
  }
  // Read as the server reads it: what it would refuse is not sent.
  proto::PartRequest parsed;
  if (!ReadRequest(request, proto::ParsePartRequest, &parsed, &error)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return error.exit_code();
  }
  ApiClient client(c.server, c.retry, c.timeout_s);
  ConfigureRetries(c, &client);
  HttpReply r;
  HttpFailure f;
  if (!client.PostJson(o.report ? "/v1/parts?report=json" : "/v1/parts", request.dump(), &r, &f)) {
    std::fprintf(stderr, "surfdeform: %s\n", f.message.c_str());
    return ExitFor(f);
  }
  const std::string bytes = o.report ? json::parse(r.body, nullptr, false).dump(2) + "\n" : r.body;
  if (!WriteFileAtomically(out_path, bytes, &error.message)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.message.c_str());
    return kExitLocalFile;
  }
  PrintReport(out_path, json::parse(o.report ? r.body : r.stats, nullptr, false));
  return kExitOk;
}

}  // namespace surfdeform::cli
