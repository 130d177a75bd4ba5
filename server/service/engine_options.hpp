// A request's settings (proto/api.hpp) as the engine's options: the
// settings as given, and how the work runs, which no request says: threads,
// what is left of the time budget, the output limits, the input format's
// axis convention. The one place the service adds them.
#pragma once

#include "engine/flatten/flatten.hpp"
#include "engine/placement/placement.hpp"
#include "engine/subdivision/subdivide.hpp"
#include "meshio/mesh_import.hpp"
#include "service/request_work.hpp"
#include "service/service_limits.hpp"

namespace surfdeform {

// The settings, with how the work runs at the engine's defaults: for work
// that sets it later, or that runs nothing (a sheet rebuilt from its bytes).
template <typename Options, typename Settings>
Options WithRunDefaults(const Settings& given) {
  Options options;
  static_cast<Settings&>(options) = given;
  return options;
}

// A flattening on `threads` (0: one per core) within what is left of the
// request's clock, at most `cap_ms`, stopped when the request is cancelled.
FlattenOptions FlattenFor(const FlattenSettings& given, int threads, const RequestClock& clock,
                          double cap_ms);

// The placement on `threads`, up +Y for glTF input (its convention) when
// the request says "auto".
PlacementOptions PlacementFor(const PlacementSettings& given, const ImportedMesh& m, int threads);

// The subdivision within this request's threads, output limits and what is
// left of its time budget.
SubdivisionOptions SubdivisionFor(const SubdivisionSettings& given, const ServiceLimits& limits,
                                  const RequestWork& work);

}  // namespace surfdeform
