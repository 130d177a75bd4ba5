#include "proto/surface_json.hpp"

namespace surfdeform::proto {

using nlohmann::json;

Status ReadFrame(JsonObject& o, const char* name, Frame* frame) {
  const json* v = o.Find(name);
  if (v == nullptr) return Status::Ok();
  SURFDEFORM_ASSIGN_OR_RETURN(auto f, JsonObject::Open(*v, o.PathOf(name)));
  SURFDEFORM_RETURN_IF_ERROR(f.Vector3("origin", &frame->origin));
  SURFDEFORM_RETURN_IF_ERROR(f.Vector3("x_axis", &frame->x_axis));
  SURFDEFORM_RETURN_IF_ERROR(f.Vector3("z_axis", &frame->z_axis));
  return f.Finish();
}

json FrameJson(const Frame& f) {
  return {{"origin", {f.origin.x(), f.origin.y(), f.origin.z()}},
          {"x_axis", {f.x_axis.x(), f.x_axis.y(), f.x_axis.z()}},
          {"z_axis", {f.z_axis.x(), f.z_axis.y(), f.z_axis.z()}}};
}

json PointsJson(const std::vector<Vec3>& points) {
  json a = json::array();
  for (const Vec3& p : points) a.push_back({p.x(), p.y(), p.z()});
  return a;
}

}  // namespace surfdeform::proto
