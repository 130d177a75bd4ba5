// The engine's reports in the replies' JSON: a flattening's quality, a
// deformation's placement and its subdivision (the "stats" of POST
// /v1/deform and /v1/animate, the "quality" of a surface).
#pragma once

#include <nlohmann/json.hpp>

#include "engine/deform/deform.hpp"
#include "engine/flatten/flatten.hpp"
#include "engine/subdivision/subdivide.hpp"

namespace surfdeform {

nlohmann::json QualityJson(const FlattenQuality& quality);
nlohmann::json DeformStatsJson(const DeformStats& stats);
nlohmann::json SubdivisionStatsJson(const SubdivisionStats& stats);

}  // namespace surfdeform
