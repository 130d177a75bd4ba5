#include "http/deform_request.hpp"

namespace surfdeform::http {

Result<DeformRequest> DeformRequestOf(const httplib::Request& req, const DeformBody& body) {
  DeformRequest d;
  d.accept = req.get_header_value("Accept");
  d.if_none_match = req.get_header_value("If-None-Match");
  d.accept_encoding = req.get_header_value("Accept-Encoding");
  // A view into the request or its body, which outlive the service's call.
  std::string_view params;
  // The parameters come from one place, once: a second copy would be
  // ignored without a word.
  const size_t in_query = req.get_param_value_count("params");
  const size_t in_header = req.get_header_value_count("X-Surfdeform-Params");
  const size_t in_form = req.is_multipart_form_data() ? body.parts.count("params") : 0;
  // A JSON body is the parameters alone (the mesh named by "model_id").
  const std::string type = req.get_header_value("Content-Type");
  const bool json_body = type.rfind("application/json", 0) == 0;
  const size_t in_body = json_body ? 1 : 0;
  if (in_query + in_header + in_form + in_body > 1) {
    return Status(ErrorCode::kMalformed,
                  "the parameters are given " +
                      std::to_string(in_query + in_header + in_form + in_body) +
                      " times (query: " + std::to_string(in_query) +
                      ", X-Surfdeform-Params "
                      "header: " +
                      std::to_string(in_header) + ", form part: " + std::to_string(in_form) +
                      ", JSON body: " + std::to_string(in_body) + "); give them once",
                  "params");
  }
  if (req.is_multipart_form_data()) {
    // No "mesh" part: the parameters name a model_id (or the service says
    // that a mesh is missing).
    if (body.parts.count("mesh") > 1) {
      return Status(ErrorCode::kMalformed, "give one \"mesh\" part and one \"params\" part",
                    "mesh");
    }
    if (auto it = body.parts.find("mesh"); it != body.parts.end()) d.mesh = it->second.content;
    if (auto it = body.parts.find("params"); it != body.parts.end()) params = it->second.content;
  } else if (json_body) {
    params = body.raw;
  } else {
    if (type.rfind("application/x-www-form", 0) == 0) {
      return Status(ErrorCode::kUnsupportedFormat,
                    "POST " + req.path +
                        " takes multipart/form-data (parts \"mesh\" and "
                        "\"params\"), the raw mesh bytes with the parameters in the "
                        "\"params\" query parameter or the X-Surfdeform-Params header, "
                        "or the parameters as an application/json body naming a "
                        "\"model_id\"",
                    "Content-Type");
    }
    d.mesh = body.raw;
    if (auto q = req.params.find("params"); q != req.params.end()) {
      params = q->second;
    } else if (auto h = req.headers.find("X-Surfdeform-Params"); h != req.headers.end()) {
      params = h->second;
    }
  }
  if (params.empty()) {
    return Status(ErrorCode::kMalformed,
                  "the deformation parameters are missing (a \"params\" JSON part, "
                  "\"params\" query parameter or X-Surfdeform-Params header); at least "
                  "{\"surface\": {...}} or {\"surface_id\": \"...\"}",
                  "params");
  }
  d.params = params;
  d.routed_surface_id = req.has_param("surface_id")
                            ? req.get_param_value("surface_id")
                            : req.get_header_value("X-Surfdeform-Surface-Id");
  return d;
}

Result<std::string_view> UploadedMesh(const httplib::Request& req, const DeformBody& body) {
  std::string_view mesh = body.raw;
  if (req.is_multipart_form_data()) {
    if (body.parts.size() != 1 || body.parts.count("mesh") != 1) {
      return Status(ErrorCode::kMalformed,
                    "POST /v1/models takes one multipart part, \"mesh\" (the mesh file), "
                    "or the file's raw bytes as the body",
                    "mesh");
    }
    mesh = body.parts.begin()->second.content;
  }
  return mesh;
}

}  // namespace surfdeform::http
