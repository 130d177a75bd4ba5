#include "service/warm_start.hpp"

#include <algorithm>
#include <numbers>
#include <variant>

#include "engine/flatten/sheet_motion.hpp"

namespace surfdeform {

using nlohmann::json;

bool SameShape(const SurfaceSpec& a, const SurfaceSpec& b) {
  if (a.index() != b.index()) return false;
  if (std::holds_alternative<MeshSpec>(a)) return false;  // flattened from the mesh each time
  if (const auto* x = std::get_if<BezierSpec>(&a)) {
    const auto& y = std::get<BezierSpec>(b);
    return x->degree_u == y.degree_u && x->degree_v == y.degree_v &&
           x->control_points.size() == y.control_points.size();
  }
  if (const auto* x = std::get_if<BSplineSpec>(&a)) {
    const auto& y = std::get<BSplineSpec>(b);
    return x->degree_u == y.degree_u && x->degree_v == y.degree_v && x->count_u == y.count_u &&
           x->count_v == y.count_v;
  }
  if (const auto* x = std::get_if<GridSpec>(&a)) {
    const auto& y = std::get<GridSpec>(b);
    return x->nu == y.nu && x->nv == y.nv;
  }
  return true;
}

WarmStart WarmStartFor(const proto::SurfaceRequest& now, std::string_view from,
                       SurfaceStore& store) {
  WarmStart w;
  w.from = from;
  if (w.from.empty()) return w;
  auto found = store.Find(w.from);
  if (!found.ok()) {
    w.reason = "unknown surface (never flattened here, or evicted)";
    return w;
  }
  const proto::SurfaceRequest& was = (*found)->request;
  if (!SameShape(was.surface, now.surface)) {
    w.reason = "another kind or shape (degrees, control grid)";
  } else if (was.sampling.nu != now.sampling.nu || was.sampling.nv != now.sampling.nv) {
    w.reason = "another sampling grid";
  } else if (proto::CanonicalJson(was)["flatten"] != proto::CanonicalJson(now)["flatten"]) {
    w.reason = "other flattening options";
  } else {
    w.entry = *found;
  }
  return w;
}

std::optional<SheetMotion> MotionOf(const WarmStart& w, const StoredSurface& made) {
  if (w.entry == nullptr || w.entry->sheet.flat.size() != made.sheet.flat.size()) {
    return std::nullopt;
  }
  auto m = BestSheetMotion(w.entry->sheet.flat, made.sheet.flat);
  if (!m.ok()) return std::nullopt;
  return *m;
}

void MovePlacement(const SheetMotion& motion, PlacementSettings* placement) {
  if (placement->center_mode == CenterMode::kSheetUnits) {
    placement->center = motion.Apply(placement->center);
  }
  placement->rotation_deg += motion.angle * 180.0 / std::numbers::pi;
}

// The reply's account of a warm start: used or not and why, and the
// iterations it saved (estimated: those of the sheet it started from, which
// a cold start of a nearby surface takes about as many of).
json WarmStartJson(const WarmStart& w, const StoredSurface& made, bool hit,
                   const std::optional<SheetMotion>& motion) {
  json j = {{"from", w.from}};
  const FlattenQuality& q = made.sheet.quality;
  // Where the surface it names (same shape and grid) lies on the new sheet,
  // used or not (a surface flattened already included): a client keeps its
  // placement on the surface by moving it so.
  if (const auto& m = motion) {
    j["motion"] = {{"rotation_deg", m->angle * 180.0 / std::numbers::pi},
                   {"translation", {m->translation.x(), m->translation.y()}},
                   {"rms", m->rms}};
  }
  std::string reason = w.reason;
  if (hit) {
    reason = "the surface was flattened already";
  } else if (made.sheet.method == "exact") {
    reason = "unrolled in closed form: nothing to iterate";
  }
  const bool used = w.entry != nullptr && reason.empty();
  j["used"] = used;
  if (!used) {
    j["reason"] = reason;
    return j;
  }
  j["iterations"] = q.iterations;
  j["iterations_saved_estimate"] = std::max(0, w.entry->sheet.quality.iterations - q.iterations);
  // Pairs measured from the paths the previous surface's distances followed
  // (0 when they were not kept, or were evicted: measured afresh).
  j["paths_reused"] = q.refollowed_paths;
  if (q.extrapolated != 0.0) j["extrapolated"] = q.extrapolated;
  return j;
}

}  // namespace surfdeform
