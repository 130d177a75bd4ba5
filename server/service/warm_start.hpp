// A POST /v1/surfaces's "warm_start": whether the surface it names can be
// the new flattening's start (same kind and shape, sampling and flattening
// options), and the reply's account of it. An unusable id means a cold
// start, never an error.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/surface_spec.hpp"
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

// The surface `create.warm_start` names, from `store`, when it fits.
WarmStart WarmStartFor(const proto::CreateSurfaceRequest& create, SurfaceStore& store);

// The reply's "warm_start" for the surface `made` (hit: found flattened).
nlohmann::json WarmStartJson(const WarmStart& w, const StoredSurface& made, bool hit);

}  // namespace surfdeform
