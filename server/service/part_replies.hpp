// POST /v1/parts's work once the request is read and admitted: the body
// grown from the surface, checked, measured against the printer's limits,
// and the reply (the part in the format asked for, or its report as JSON).
#pragma once

#include <string>

#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "engine/surface/surface.hpp"
#include "proto/api.hpp"
#include "service/reply.hpp"
#include "service/request_clock.hpp"
#include "service/service_limits.hpp"

namespace surfdeform {

// The body's vertices and triangles before it is made, for the limits.
Status CheckPartSize(const proto::PartRequest& request, const Surface& surface,
                     const ServiceLimits& limits);

// The part, or its report when `report_json`. `surface_id`: the stored
// surface it was grown from (empty: inline). Errors: the body's
// (ThickenSurface), a failed check (kDegenerate naming it), with strict a
// wall under the printer's minimum (kInvalidArgument with the limit and the
// wall), and `clock`'s between the steps (its budget spent, or the client
// gone).
Result<Reply> MakePartReply(const proto::PartRequest& request, const Surface& surface,
                            const std::string& surface_id, proto::OutputFormat format,
                            bool report_json, const RequestClock& clock);

// An uploaded body's memory estimate, before it is checked.
Status CheckUploadedPartSize(const Mesh& body, const ServiceLimits& limits);

// An uploaded body (body.model_id) checked and sent as it is: a closed
// mesh, or kDegenerate naming the first check it fails (for a body that
// is not closed, how many edges border one triangle and where).
Result<Reply> MakeUploadedPartReply(const proto::PartRequest& request, const Mesh& body,
                                    proto::OutputFormat format, bool report_json,
                                    const RequestClock& clock);

}  // namespace surfdeform
