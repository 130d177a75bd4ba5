#include "service/output_negotiation.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "base/header_lists.hpp"

namespace surfdeform {
namespace {

// A media type in lower case (media types are case-insensitive).
std::string Lowered(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

std::optional<proto::OutputFormat> FormatOfMediaType(const std::string& type) {
  using proto::OutputFormat;
  if (type == "application/octet-stream" || type == "application/x-draco" ||
      type == "application/vnd.google.draco" || type == "*/*" || type == "application/*") {
    return OutputFormat::kDrc;
  }
  if (type == "model/gltf-binary" || type == "model/*") return OutputFormat::kGlb;
  if (type == "model/obj" || type == "text/plain" || type == "text/*") return OutputFormat::kObj;
  if (type == "application/x-ply" || type == "application/ply") return OutputFormat::kPly;
  if (type == "model/stl" || type == "application/sla") return OutputFormat::kStl;
  if (type == "model/3mf" || type == "application/vnd.ms-package.3dmanufacturing-3dmodel+xml") {
    return OutputFormat::k3mf;
  }
  return std::nullopt;
}

// The media types of an Accept header in order, lower case, without those
// refused by q=0: f(type) until it returns true. True when one did.
template <typename F>
bool FirstAccepted(std::string_view accept, F&& f) {
  return AnyHeaderListItem(
      accept, [&f](const HeaderListItem& item) { return !item.refused && f(Lowered(item.value)); });
}

}  // namespace

Result<proto::OutputFormat> ChooseOutputFormat(std::optional<proto::OutputFormat> requested,
                                               std::string_view accept) {
  if (requested) return *requested;
  if (TrimHttpSpace(accept).empty()) return proto::OutputFormat::kDrc;
  std::optional<proto::OutputFormat> chosen;
  if (FirstAccepted(accept, [&](const std::string& type) {
        chosen = FormatOfMediaType(type);
        return chosen.has_value();
      })) {
    return *chosen;
  }
  return Status(ErrorCode::kNotAcceptable,
                "the Accept header names no format this server writes; accept "
                "application/octet-stream (Draco), model/gltf-binary, model/obj, "
                "application/x-ply, model/stl or model/3mf, or set output.format in the parameters",
                "Accept");
}

bool PrefersBytesToJson(std::string_view accept) {
  bool bytes = false;
  FirstAccepted(accept, [&bytes](const std::string& type) {
    bytes = type == "application/octet-stream";
    return bytes || type == "application/json";
  });
  return bytes;
}

Status AcceptGlbOnly(std::string_view accept) {
  if (TrimHttpSpace(accept).empty()) return Status::Ok();
  // What ChooseOutputFormat reads as a GLB, and */* (which it gives Draco).
  if (FirstAccepted(accept, [](const std::string& type) {
        return type == "*/*" || FormatOfMediaType(type) == proto::OutputFormat::kGlb;
      })) {
    return Status::Ok();
  }
  return Status(
      ErrorCode::kNotAcceptable,
      "this answer is a GLB (model/gltf-binary); the Accept header asks for " + std::string(accept),
      "Accept");
}

Status CheckDistortionFormat(const proto::OutputOptions& o, proto::OutputFormat format) {
  using F = proto::OutputFormat;
  if (!o.distortion || format == F::kGlb || format == F::kGlbPlain || format == F::kPly) {
    return Status::Ok();
  }
  return InvalidArgument(std::string("the distortion map is written in glb, glb_plain or ply "
                                     "output (a _DISTORTION attribute, or two PLY properties); "
                                     "the output format is ") +
                             proto::OutputFormatName(format),
                         "output.distortion");
}

MeshFormat OutputMeshFormat(proto::OutputFormat format) {
  switch (format) {
    case proto::OutputFormat::kDrc:
      return MeshFormat::kDraco;
    case proto::OutputFormat::kGlb:
    case proto::OutputFormat::kGlbPlain:
      return MeshFormat::kGlb;
    case proto::OutputFormat::kObj:
      return MeshFormat::kObj;
    case proto::OutputFormat::kPly:
      return MeshFormat::kPly;
    case proto::OutputFormat::kStl:
      return MeshFormat::kStl;
    case proto::OutputFormat::k3mf:
      return MeshFormat::k3mf;
  }
  return MeshFormat::kDraco;
}

}  // namespace surfdeform
