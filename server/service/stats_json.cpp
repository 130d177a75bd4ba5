#include "service/stats_json.hpp"

namespace surfdeform {

using nlohmann::json;

json QualityJson(const FlattenQuality& q) {
  return {{"stress", q.stress},
          {"max_edge_error", q.max_edge_error},
          {"area_ratio_min", q.area_ratio_min},
          {"area_ratio_max", q.area_ratio_max},
          {"folded_cells", q.folded_cells},
          {"iterations", q.iterations},
          {"converged", q.converged}};
}

json SubdivisionStatsJson(const SubdivisionStats& s) {
  return {{"mode", SubdivisionModeName(s.mode)},
          {"vertices_before", s.vertices_before},
          {"triangles_before", s.triangles_before},
          {"vertices_after", s.vertices_after},
          {"triangles_after", s.triangles_after},
          {"vertices_added", s.vertices_after - s.vertices_before},
          {"edge_points_considered", s.edge_points_considered},
          {"edge_points_kept", s.edge_points_kept},
          {"face_points_considered", s.face_points_considered},
          {"face_points_kept", s.face_points_kept},
          {"refinement_points", s.refinement_points},
          {"epsilon", s.epsilon},
          {"tolerance", s.tolerance},
          {"max_deviation", s.max_deviation},
          {"max_estimated_deviation", s.max_estimated_deviation},
          {"measured_points", s.measured_points}};
}

json DeformStatsJson(const DeformStats& s) {
  json j = {{"vertices", s.vertices},  {"triangles", s.triangles},
            {"outside", s.outside},    {"max_outside_distance", s.max_outside_distance},
            {"scale", s.scale},        {"up", NameOf<UpAxis>(kUpAxes, s.up)},
            {"up_reason", s.up_reason}};
  if (s.fit_frame >= 0) j["fit_frame"] = s.fit_frame;
  if (s.turns > 0.0) j["turns"] = s.turns;  // round a closed surface
  return j;
}

}  // namespace surfdeform
