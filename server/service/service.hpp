// What each request does, independent of HTTP: parse and validate, flatten
// (through the surface cache), import, deform, export. The HTTP layer calls
// this and maps its Status codes to HTTP in one place.
//
// Free of Eigen and of HTTP headers on purpose: httplib.h and Eigen must not
// meet in one translation unit (docs/ARCHITECTURE.md).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/cancel_flag.hpp"
#include "base/status.hpp"
#include "service/admission.hpp"
#include "service/placement_memo_stats.hpp"
#include "service/reply.hpp"
#include "service/service_limits.hpp"
#include "service/shared_tier.hpp"
#include "service/single_flight_cache.hpp"

namespace surfdeform {

struct ServiceOptions {
  ServiceLimits limits;
  int engine_threads = 0;  // threads per flattening or deformation; 0 = one per core
  // The cache's second level, shared by replicas (Redis); null: in-process only.
  std::shared_ptr<SharedTier> shared_tier;
};

struct DeformRequest {
  std::string_view mesh;    // the mesh file's bytes (empty: the parameters name a model_id)
  std::string_view params;  // the parameters' JSON
  std::string accept;       // the Accept header (used when params name no format)
  // The X-Surfdeform-Surface-Id header or surface_id query parameter, which
  // load balancers route by: the surface when the parameters name none, and
  // otherwise it must be the one they name.
  std::string routed_surface_id{};
  // The If-None-Match header: an answer whose ETag it names is 304 (Reply::
  // not_modified), decided before any work on the model.
  std::string if_none_match{};
  // The Accept-Encoding header: an answer that compresses is made gzipped
  // too when it accepts gzip (Reply::gzip_body).
  std::string accept_encoding{};
  // Raised when nobody waits for the answer any more (the client left, the
  // server stops): the work stops at its next checkpoint. May be null.
  const CancelFlag* cancel = nullptr;
};

class Service {
 public:
  explicit Service(ServiceOptions options);
  ~Service();
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  // POST /v1/surfaces; with a `field_side` the reply carries the field of
  // that side too ("field", as GetSurfaceField's JSON): one round trip.
  // Each call that works takes the request's cancel flag (may be null; see
  // DeformRequest::cancel).
  Result<Reply> CreateSurface(std::string_view body, std::string_view field_side = {},
                              const CancelFlag* cancel = nullptr);
  // GET /v1/surfaces/{id}/field?n=: JSON, or bytes for an Accept that prefers
  // application/octet-stream (replies.hpp has the layout).
  Result<Reply> GetSurfaceField(std::string_view id, std::string_view side,
                                std::string_view accept);
  Result<Reply> GetSurface(std::string_view id);     // GET /v1/surfaces/{id}
  Result<Reply> GetSurfaceSvg(std::string_view id);  // GET /v1/surfaces/{id}/flat.svg
  // POST /v1/models: a mesh file's bytes. `routed_id` (the
  // X-Surfdeform-Model-Id header, which load balancers route by), when
  // given, must be the id the bytes have.
  // POST /v1/fonts: a TTF, OTF, WOFF or WOFF2 file's bytes, read behind the
  // font limits and kept by content id (like models).
  Result<Reply> UploadFont(std::string_view bytes, const CancelFlag* cancel = nullptr);
  // GET /v1/fonts: the built-in fonts, the scripts each covers, and the
  // limits on uploaded ones.
  Result<Reply> ListFonts();
  Result<Reply> GetFont(std::string_view name_or_id);  // GET /v1/fonts/{id}
  // POST /v1/text: the text's mesh alone, flat, in mm (what a deformation
  // with this text lays on the sheet), as OBJ, PLY, GLB or Draco: for
  // previews, and for a mesh of the words.
  Result<Reply> MakeText(std::string_view body, std::string_view accept,
                         const CancelFlag* cancel = nullptr);
  // POST /v1/parts: one closed solid grown from a surface (inline or by
  // id), checked, in millimetres, as 3MF (the default), STL or any mesh
  // format; with report "json", its report instead.
  Result<Reply> MakePart(std::string_view body, std::string_view accept, std::string_view report,
                         const CancelFlag* cancel = nullptr);
  Result<Reply> UploadModel(std::string_view mesh, std::string_view routed_id,
                            const CancelFlag* cancel = nullptr);
  Result<Reply> GetModel(std::string_view id);          // GET /v1/models/{id}
  Result<Reply> Deform(const DeformRequest& request);   // POST /v1/deform
  Result<Reply> Animate(const DeformRequest& request);  // POST /v1/animate
  // POST /v1/surfaces/{id}/map (proto/map_api.hpp)
  Result<Reply> MapOnSurface(std::string_view id, std::string_view body,
                             const CancelFlag* cancel = nullptr);

  nlohmann::json InfoJson() const;  // GET /v1/info (the HTTP layer adds its own limits)
  // Where uploads and flattened surfaces are kept, and for how long.
  Retention retention() const;
  CacheStats cache_stats() const;
  CacheStats model_cache_stats() const;
  CacheStats answer_cache_stats() const;
  // The distance paths kept for live edits (SurfaceStore::Flattened).
  CacheStats edit_paths_stats() const;
  PlacementMemoStats placement_memo_stats() const;
  SharedTierStats shared_tier_stats() const;  // enabled = false without one
  AdmissionStats admission_stats() const;
  // Every slot busy and the queue full: a new request would be refused now
  // (the HTTP layer refuses it before reading its body).
  bool Saturated() const;
  int RetryAfterSeconds() const;  // for a 503: from the measured service time and the queue
  const ServiceLimits& limits() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace surfdeform
