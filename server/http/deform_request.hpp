// The bodies of the routes that read their own (POST /v1/deform,
// /v1/animate, /v1/models), and the requests the service takes from them.
#pragma once

#include <httplib.h>

#include <map>
#include <string>
#include <string_view>

#include "base/status.hpp"
#include "service/service.hpp"

namespace surfdeform::http {

// A deformation's body as its handler reads it.
struct DeformBody {
  std::string raw;                                               // a raw mesh
  std::multimap<std::string, httplib::MultipartFormData> parts;  // or a form's parts
};

// POST /v1/deform and POST /v1/animate: one mesh and its parameters, in the
// same body forms (multipart "mesh" and "params"; the raw mesh with the
// parameters in the "params" query parameter or the X-Surfdeform-Params
// header; or the parameters alone as a JSON body naming a "model_id"). The
// parameters come from one place, once. The request's views point into `req`
// and `body`.
Result<DeformRequest> DeformRequestOf(const httplib::Request& req, const DeformBody& body);

// POST /v1/models: the mesh file, as the raw body or a multipart "mesh" part.
Result<std::string_view> UploadedMesh(const httplib::Request& req, const DeformBody& body);

}  // namespace surfdeform::http
