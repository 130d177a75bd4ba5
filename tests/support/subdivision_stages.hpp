// The inputs of the subdivision's stages, built the way Subdivide builds
// them, for the per-stage unit tests (tests/unit/subdivision/).
#pragma once

#include <memory>
#include <optional>

#include "engine/placement/placement.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/subdivision/assembly.hpp"
#include "engine/subdivision/screen.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform::testing {

// Owns everything a Context refers to; built once, never moved.
struct StageInputs {
  Target target;
  Mesh mesh;
  PlacementOptions placement;
  SubdivisionOptions options;
  std::unique_ptr<SheetMap> map;
  std::vector<Vec3> placed;
  std::unique_ptr<subdivision::Context> ctx;

  // The stages up to each one, as Subdivide runs them (a failure is a test
  // failure).
  subdivision::LocatedVertices Located(bool positions = true) const;
  subdivision::GridMarking Marked(const subdivision::EdgeGraph& graph,
                                  const subdivision::LocatedVertices& located,
                                  const subdivision::CellEstimates& estimates) const;
};

// `mesh` placed on `target` with `placement` (fit with a 5% margin unless
// given), for `options`.
std::unique_ptr<StageInputs> MakeStageInputs(Target target, Mesh mesh,
                                             const SubdivisionOptions& options,
                                             std::optional<PlacementOptions> placement = {});

// Everything from the marking to the faces, for the assembly's tests.
struct StagesThroughFaces {
  subdivision::LocatedVertices located;
  std::unique_ptr<subdivision::CellEstimates> estimates;
  subdivision::EdgeGraph graph;
  subdivision::GridMarking marking;
  subdivision::IdVector<subdivision::EdgeId, subdivision::RefinedEdge> edges;
  subdivision::IdVector<subdivision::FaceId, subdivision::FaceOutput> faces;
};
std::unique_ptr<StagesThroughFaces> RunThroughFaces(const StageInputs& in);

}  // namespace surfdeform::testing
