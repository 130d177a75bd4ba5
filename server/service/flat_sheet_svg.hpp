// A picture of a flat sheet: its grid cells coloured by local stretch (the
// ratio of each cell's flat area to its area on the surface, on a log scale:
// blue where the sheet is compressed, white where exact, red where
// stretched), with a legend, and on a surface closed in u (periodic_u) or v
// (periodic_v) its seams dashed. Deterministic text: same sheet, same bytes.
#pragma once

#include <string>

#include "engine/flatten/flatten.hpp"

namespace surfdeform {

// A surface given as a mesh (`mesh`) is drawn as its flat triangles, in
// the sheet's frame, each coloured by its own area ratio.
std::string FlatSheetSvg(const FlatSheet& sheet, const std::string& title, bool periodic_u = false,
                         bool periodic_v = false, const FlatMesh* mesh = nullptr);

}  // namespace surfdeform
