#include "support/subdivision_stages.hpp"

#include <limits>

#include "support/expect_ok.hpp"

namespace surfdeform::testing {

using namespace subdivision;

std::unique_ptr<StageInputs> MakeStageInputs(Target target, Mesh mesh,
                                             const SubdivisionOptions& options,
                                             std::optional<PlacementOptions> placement) {
  auto in = std::make_unique<StageInputs>();
  in->target = std::move(target);
  in->mesh = std::move(mesh);
  in->options = options;
  if (placement) {
    in->placement = *placement;
  } else {
    in->placement.fit = true;
    in->placement.fit_margin = 0.05;
  }
  in->map = std::make_unique<SheetMap>(*in->target.surface, in->target.sheet);
  auto pl = ComputePlacement(*in->map, in->mesh.positions, in->placement);
  ExpectOk(pl);
  if (!pl.ok()) return in;
  for (const Vec3& p : in->mesh.positions) in->placed.push_back(pl->Apply(p));
  in->ctx =
      std::make_unique<Context>(in->mesh, in->placed, *in->map, in->placement.outside, in->options);
  return in;
}

LocatedVertices StageInputs::Located(bool positions) const {
  auto located = LocateVertices(*ctx, positions);
  ExpectOk(located);
  return located.ok() ? std::move(located).value() : LocatedVertices{};
}

GridMarking StageInputs::Marked(const EdgeGraph& graph, const LocatedVertices& located,
                                const CellEstimates& estimates) const {
  // Unbounded here: the later stages' tests set small output limits for
  // themselves (the marking's bound has its own test).
  SubdivisionOptions unbounded = options;
  unbounded.max_vertices = std::numeric_limits<size_t>::max() / 2;
  Budget budget(unbounded, mesh.positions.size());
  GridMarking marking = FindGridPoints(*ctx, graph, located.cell, estimates, &budget);
  MarkGridPoints(*ctx, graph, &marking);
  return marking;
}

std::unique_ptr<StagesThroughFaces> RunThroughFaces(const StageInputs& in) {
  auto s = std::make_unique<StagesThroughFaces>();
  s->located = in.Located();
  s->estimates = std::make_unique<CellEstimates>(*in.ctx, s->located.cell);
  s->graph = BuildEdgeGraph(in.mesh);
  s->marking = in.Marked(s->graph, s->located, *s->estimates);
  Budget budget(in.options, in.mesh.positions.size());
  s->edges = RefineEdges(*in.ctx, s->graph, s->marking, s->located, *s->estimates, &budget);
  const FaceStageInputs inputs{*in.ctx, s->graph, s->marking, s->edges, s->located, *s->estimates};
  s->faces = RefineFaces(inputs, &budget);
  return s;
}

}  // namespace surfdeform::testing
