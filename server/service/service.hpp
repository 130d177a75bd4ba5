// What each request does, independent of HTTP: parse and validate, flatten
// (through the surface cache), import, deform, export. The HTTP layer calls
// this and maps its Status codes to HTTP in one place.
//
// Free of Eigen and of HTTP headers on purpose: httplib.h and Eigen must not
// meet in one translation unit (see DESIGN.md).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.hpp"
#include "service/admission.hpp"
#include "service/placement_memo_stats.hpp"
#include "service/shared_tier.hpp"
#include "service/single_flight_cache.hpp"

namespace surfdeform {

// Published in GET /v1/info; every one is configurable from the command line.
struct ServiceLimits {
  size_t max_body_bytes = 64u << 20;  // request body (mesh plus parameters)
  size_t max_vertices = 2'000'000;    // input mesh, after triangulation
  size_t max_triangles = 4'000'000;
  int max_grid_side = 256;                 // sampling nu and nv (the engine allows 512)
  size_t max_output_vertices = 4'000'000;  // the mesh after subdivision
  size_t max_output_triangles = 8'000'000;
  int max_json_depth = 32;                // request JSON nesting (glTF JSON: twice this)
  int max_in_flight = 0;                  // flatten/deform requests running at once; 0 = 1 per core
  int max_queued = -1;                    // more that wait for a slot; -1 = 4 per core
  double queue_timeout_ms = 5000;         // the longest wait for a slot (then 503)
  double flatten_time_budget_ms = 20000;  // a flattening that takes longer fails (413)
  // A request's parsing, flattening, deformation and subdivision together;
  // past it the request fails (413). The encoding that follows is bounded by
  // the output size limits instead.
  double request_time_budget_ms = 60000;
  size_t cache_bytes = 256u << 20;
  // Where the vertices of models that come back lie on their sheets
  // (service/placement_memo.hpp): 24 bytes a vertex, 0.9 MB for the bunny.
  size_t footprint_memo_bytes = 64u << 20;
  // Animations (POST /v1/animate, and /v1/deform with a frame): frames, and
  // frames times the model's vertices after subdivision (the frames are held
  // in memory, 24 bytes per vertex), and the GLB's size.
  int max_animation_frames = 600;
  size_t max_animation_frame_vertices = 8'000'000;
  size_t max_animation_bytes = 256u << 20;
  // The memory one request may take for its work, estimated before the work
  // from its counts (server/service/memory_budget.hpp): a request past it is
  // refused (413) at once, and the subdivision's and the map's output limits
  // shrink to fit it. With max_in_flight, it bounds the memory that work in
  // flight takes, besides the caches.
  size_t request_memory_bytes = 1u << 30;
};

struct ServiceOptions {
  ServiceLimits limits;
  int engine_threads = 0;  // threads per flattening or deformation; 0 = one per core
  // The cache's second level, shared by replicas (Redis); null: in-process only.
  std::shared_ptr<SharedTier> shared_tier;
};

struct Timing {
  std::string name;  // parse, flatten, deform, encode
  double ms = 0.0;
};

struct Reply {
  std::string body;
  std::string content_type;
  std::vector<Timing> timings;
  std::string stats_json;  // for a response header: counts, quality
  std::string etag;        // over the body bytes (deterministic)
  bool cache_hit = false;
  std::string surface_id;  // CreateSurface: the id of the flattened surface
};

struct DeformRequest {
  std::string_view mesh;    // the mesh file's bytes
  std::string_view params;  // the parameters' JSON
  std::string accept;       // the Accept header (used when params name no format)
  // The X-Surfdeform-Surface-Id header or surface_id query parameter, which
  // load balancers route by: the surface when the parameters name none, and
  // otherwise it must be the one they name.
  std::string routed_surface_id{};
};

class Service {
 public:
  explicit Service(ServiceOptions options);
  ~Service();
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  Result<Reply> CreateSurface(std::string_view body);   // POST /v1/surfaces
  Result<Reply> GetSurface(std::string_view id);        // GET /v1/surfaces/{id}
  Result<Reply> GetSurfaceSvg(std::string_view id);     // GET /v1/surfaces/{id}/flat.svg
  Result<Reply> Deform(const DeformRequest& request);   // POST /v1/deform
  Result<Reply> Animate(const DeformRequest& request);  // POST /v1/animate
  // POST /v1/surfaces/{id}/map (proto/map_api.hpp)
  Result<Reply> MapOnSurface(std::string_view id, std::string_view body);

  std::string InfoJson() const;  // GET /v1/info
  CacheStats cache_stats() const;
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
