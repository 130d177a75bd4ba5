// A POST /v1/surfaces's "warm_start": whether the surface it names can be
// the new flattening's start (same kind and shape, sampling and flattening
// options), and the reply's account of it. An unusable id means a cold
// start, never an error.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "engine/common/placement_settings.hpp"
#include "engine/flatten/sheet_motion.hpp"
#include "engine/surface/surface_spec.hpp"
#include "proto/api.hpp"
#include "service/surface_store.hpp"

namespace surfdeform {

// Whether two surfaces have one shape (kind, degrees, control grid): an edit
// of one starts well from the other's sheet.
bool SameShape(const SurfaceSpec& a, const SurfaceSpec& b);

struct WarmStart {
  std::string from;                            // the id asked for ("": none)
  std::shared_ptr<const StoredSurface> entry;  // null: a cold start
  std::string reason;                          // then why
};

// The surface `from` names, from `store`, when it fits `now`.
WarmStart WarmStartFor(const proto::SurfaceRequest& now, std::string_view from,
                       SurfaceStore& store);
inline WarmStart WarmStartFor(const proto::CreateSurfaceRequest& create, SurfaceStore& store) {
  return WarmStartFor(create.request, create.warm_start, store);
}

// How the sheet of the surface the warm start names lies on `made`'s sheet,
// whether the warm start was used or not (`made` may have been flattened
// already): known where both are held and share a grid.
std::optional<SheetMotion> MotionOf(const WarmStart& w, const StoredSurface& made);

// A placement given on the warm start's sheet, moved onto the new one: a
// centre in sheet units by the motion, and the rotation by its angle, so the
// model stays on the same part of the surface. A centre given as the
// sheet's centre (the image of the surface's middle) or as a fraction of
// its box is left as given.
void MovePlacement(const SheetMotion& motion, PlacementSettings* placement);

// The reply's "warm_start" for the surface `made` (hit: found flattened),
// with `motion` (MotionOf(w, made), which a caller may have found already).
nlohmann::json WarmStartJson(const WarmStart& w, const StoredSurface& made, bool hit,
                             const std::optional<SheetMotion>& motion);
inline nlohmann::json WarmStartJson(const WarmStart& w, const StoredSurface& made, bool hit) {
  return WarmStartJson(w, made, hit, MotionOf(w, made));
}

}  // namespace surfdeform
