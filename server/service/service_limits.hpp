// The service's limits: what one request may ask for and take. Every room of
// the service reads them; each is published in GET /v1/info and set from the
// command line (server/main.cpp).
#pragma once

#include <string>

#include "service/builtin_fonts.hpp"
#include "text/font_face.hpp"

#include <cstddef>

namespace surfdeform {

// Published in GET /v1/info; every one is configurable from the command line.
struct ServiceLimits {
  size_t max_body_bytes = 64u << 20;  // request body (mesh plus parameters)
  size_t max_vertices = 2'000'000;    // input mesh, after triangulation
  size_t max_triangles = 4'000'000;
  int max_grid_side = 256;  // sampling nu and nv (the engine allows 512)
  // A surface given as a mesh (kind "mesh"): its vertices after welding.
  size_t max_surface_mesh_vertices = 200'000;
  // And its vertex pairs within max(flatten.range, 3) rings (some 18 a
  // vertex at range 3 on an even mesh; a vertex joining very many triangles
  // makes them quadratic).
  size_t max_surface_mesh_pairs = 8'000'000;
  size_t max_output_vertices = 4'000'000;  // the mesh after subdivision
  size_t max_output_triangles = 8'000'000;
  int max_json_depth = 32;  // request JSON nesting (glTF JSON: twice this)
  // Request JSON's values of any kind, and the bytes of its keys and
  // strings, checked as it is read (json/bounded_json.hpp): a document
  // takes up to ~100 bytes a value (an empty object in an array), 200 MB at
  // the limit; a 512 x 512 grid surface's points are 1.05M values.
  size_t max_json_elements = 2'000'000;
  size_t max_json_string_bytes = 16u << 20;
  // The values of the JSON documents of all requests held at once: past
  // it a request is refused (503) as its parse reaches it.
  size_t max_json_elements_in_flight = 8'000'000;
  int max_in_flight = 0;                  // flatten/deform requests running at once; 0 = 1 per core
  int max_queued = -1;                    // more that wait for a slot; -1 = 4 per core
  double queue_timeout_ms = 5000;         // the longest wait for a slot (then 503)
  double flatten_time_budget_ms = 20000;  // a flattening that takes longer fails (413)
  // A request's parsing, flattening, deformation and subdivision together;
  // past it the request fails (413). The encoding that follows is bounded by
  // the output size limits instead.
  double request_time_budget_ms = 60000;
  // GET /v1/surfaces/{id}/field: lattice points per side (52 bytes each).
  int max_field_side = 512;
  size_t cache_bytes = 256u << 20;
  // Uploaded models (POST /v1/models), imported: ~60 bytes a vertex for a
  // plain mesh, plus the file's size; 2.4 MB for the bunny.
  size_t model_cache_bytes = 256u << 20;
  // Fonts: what one may cost (text/font_face.hpp), where the built-in ones
  // are, and how many bytes of uploaded fonts the first level keeps.
  FontLimits font;
  std::string font_dir = kDefaultFontDir;
  size_t font_cache_bytes = 64u << 20;
  // Where the vertices of models that come back lie on their sheets
  // (service/placement_memo.hpp): 24 bytes a vertex, 0.9 MB for the bunny.
  size_t footprint_memo_bytes = 64u << 20;
  // Encoded answers of POST /v1/deform kept by their key (answer_cache.hpp);
  // 0: none kept.
  size_t answer_cache_bytes = 256u << 20;
  // A Draco GLB answer of more vertices is written in pieces encoded in
  // parallel (when cores are idle; meshio's GlbPieces); 0: never.
  size_t glb_split_vertices = 150'000;
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

}  // namespace surfdeform
