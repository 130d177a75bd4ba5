// Subdivision stage: the paper's edge and face points and marking rules.
#include "engine/subdivision/grid_marking.hpp"

#include <gtest/gtest.h>

#include "stage_test_util.hpp"

namespace surfdeform::subdivision {
namespace {

struct Marked {
  std::unique_ptr<testing::StageInputs> in;
  EdgeGraph graph;
  GridMarking marking;
};

Marked MarkOn(testing::Target target, Mesh mesh, const SubdivisionOptions& options) {
  Marked m;
  m.in = testing::MakeStageInputs(std::move(target), std::move(mesh), options);
  const LocatedVertices l = m.in->Located();
  const CellEstimates e(*m.in->ctx, l.cell);
  m.graph = BuildEdgeGraph(m.in->mesh);
  m.marking = m.in->Marked(m.graph, l, e);
  return m;
}

size_t Count(const GridMarking& g, bool marked_only) {
  size_t n = 0;
  for (const EdgeMarks& e : g.edges)
    for (const EdgePoint& p : e.points) n += !marked_only || p.marked;
  return n;
}

// A cylinder bends along u only: with epsilon below 1/r every crossing of a
// u-line is needed, and one of a v-line only (a circle of constant height,
// along which the surface is straight across) never is.
TEST(GridMarking, OnACylinderTheULineCrossingsAreMarkedAndTheVLineOnesAreNot) {
  SubdivisionOptions eps;
  eps.epsilon = 0.9;  // just below 1 / r = 1
  const Marked m = MarkOn(testing::Cylinder(1.0), testing::ThinPlate(2.4, 1.6, 0.05), eps);
  size_t u = 0, v = 0;
  for (const EdgeMarks& e : m.marking.edges) {
    if (!e.candidate) continue;
    for (const EdgePoint& p : e.points) {
      if (p.crossing.u_line >= 0) {
        EXPECT_NEAR(p.curvature, 1.0, 1e-9);
        EXPECT_TRUE(p.marked);
        ++u;
      } else {
        EXPECT_NEAR(p.curvature, 0.0, 1e-9);
        EXPECT_FALSE(p.marked);
        ++v;
      }
    }
  }
  EXPECT_GT(u, 10u);
  EXPECT_GT(v, 10u);
}

// The seed rule alone, on the same cylinder: a point is marked exactly when
// its curvature exceeds the threshold.
TEST(GridMarking, SeedsAreThePointsAboveTheThreshold) {
  for (double epsilon : {0.9, 1.1}) {
    SubdivisionOptions eps;
    eps.epsilon = epsilon;
    auto in =
        testing::MakeStageInputs(testing::Cylinder(1.0), testing::ThinPlate(2.4, 1.6, 0.05), eps);
    const LocatedVertices l = in->Located();
    const CellEstimates e(*in->ctx, l.cell);
    const EdgeGraph g = BuildEdgeGraph(in->mesh);
    Budget budget(in->options, in->mesh.positions.size());
    GridMarking m = FindGridPoints(*in->ctx, g, l.cell, e, &budget);
    SeedEdgePoints(*in->ctx, &m);
    size_t u = 0;
    for (const EdgeMarks& em : m.edges) {
      if (!em.candidate) continue;
      EXPECT_EQ(em.threshold, epsilon);
      for (const EdgePoint& p : em.points) {
        EXPECT_EQ(p.marked, p.curvature > epsilon) << epsilon;
        u += p.crossing.u_line >= 0 && p.marked;
      }
    }
    if (epsilon < 1.0) {
      EXPECT_GT(u, 10u);
    } else {
      EXPECT_EQ(u, 0u);
    }
  }
}

// Every crossing of a model's edge with a grid line is kept to be measured
// (and maybe marked), so they count against a limit of their own
// (max_crossings, which the service sets from its memory budget) before
// they are stored: 50,000 slivers across a 128 x 128 sheet made 11.8M of
// them, 1.25 GB.
TEST(GridMarking, TheCrossingsAreCountedAgainstTheirLimit) {
  const Mesh plate = testing::ThinPlate(2.4, 1.6, 0.05);
  auto count = [&](size_t limit, size_t* crossings) {
    SubdivisionOptions o = testing::Tolerance(1e-3);
    o.max_crossings = limit;
    auto in = testing::MakeStageInputs(testing::Cylinder(1.0), plate, o);
    const LocatedVertices l = in->Located();
    const CellEstimates e(*in->ctx, l.cell);
    const EdgeGraph g = BuildEdgeGraph(in->mesh);
    Budget budget(in->options, in->mesh.positions.size());
    const GridMarking m = FindGridPoints(*in->ctx, g, l.cell, e, &budget);
    *crossings = 0;
    for (const EdgeMarks& em : m.edges) *crossings += em.points.size();
    return budget.TooManyCrossings();
  };
  size_t all = 0, stopped = 0;
  EXPECT_FALSE(count(1'000'000, &all));
  ASSERT_GT(all, 40u);
  EXPECT_TRUE(count(all / 2, &stopped));
  EXPECT_LE(stopped, all / 2);  // the search stops before storing past the limit
  EXPECT_FALSE(count(all, &stopped));
  EXPECT_EQ(stopped, all);
}

TEST(GridMarking, OnAPlaneNothingIsMarkedThoughEverythingIsConsidered) {
  const Marked m = MarkOn(testing::Flattened(testing::PlaneSpec(), 8),
                          testing::ThinPlate(1.5, 1.2, 0.1), testing::Tolerance(1e-6));
  EXPECT_GT(Count(m.marking, false), 0u);
  EXPECT_EQ(Count(m.marking, true), 0u);
  for (const FaceMarks& f : m.marking.faces)
    for (const FacePoint& p : f.points) EXPECT_FALSE(p.kept);
}

TEST(GridMarking, UniformMarksEveryPointOfEveryFace) {
  SubdivisionOptions uniform;
  uniform.mode = SubdivisionMode::kUniform;
  const Marked m = MarkOn(testing::Cylinder(1.0), testing::ThinPlate(2.4, 1.6, 0.05), uniform);
  EXPECT_EQ(Count(m.marking, true), Count(m.marking, false));
  for (const FaceMarks& f : m.marking.faces) EXPECT_TRUE(f.large);
}

// The fixed point: a kept chord is kept whole, so every edge point on it is
// marked, in every face; and a face point where two kept chords cross is kept.
TEST(GridMarking, KeptChordsAreKeptWholeInEveryFace) {
  const Marked m = MarkOn(testing::Figure(10, 16), testing::ThinPlate(1.0, 1.0, 0.02),
                          testing::Tolerance(0.005));
  size_t kept = 0, crossings = 0;
  for (size_t fi = 0; fi < m.graph.faces.size(); ++fi) {
    const FaceId f(fi);
    if (!m.marking.faces[f].large) continue;
    std::vector<int> kept_lines(m.marking.faces[f].points.size(), 0);
    for (const Chord& chord : Chords(*m.in->ctx, m.graph, m.marking, f)) {
      if (!ChordKept(*m.in->ctx, m.graph, m.marking, f, chord)) continue;
      ++kept;
      for (const ChordEntry& e : chord.entries) {
        if (e.IsEdgePoint()) {
          EXPECT_TRUE(m.marking.edges[m.graph.faces[f].edge[e.side]].points[e.ref].marked);
        } else {
          ++kept_lines[e.ref];
        }
      }
    }
    for (size_t q = 0; q < kept_lines.size(); ++q) {
      if (kept_lines[q] == 2) {
        EXPECT_TRUE(m.marking.faces[f].points[q].kept);
        ++crossings;
      }
    }
  }
  EXPECT_GT(kept, 0u);
  EXPECT_GT(crossings, 0u);
}

TEST(GridMarking, ChordsRunFromEdgePointToEdgePointAlongTheirLine) {
  const Marked m = MarkOn(testing::Cylinder(1.0), testing::ThinPlate(2.4, 1.6, 0.05), {});
  for (size_t fi = 0; fi < m.graph.faces.size(); ++fi) {
    for (const Chord& chord : Chords(*m.in->ctx, m.graph, m.marking, FaceId(fi))) {
      ASSERT_FALSE(chord.entries.empty());
      if (chord.entries.size() == 1) {
        EXPECT_FALSE(chord.entries[0].IsEdgePoint());  // a lone face point
        continue;
      }
      EXPECT_TRUE(chord.entries.front().IsEdgePoint());
      EXPECT_TRUE(chord.entries.back().IsEdgePoint());
      for (size_t k = 1; k + 1 < chord.entries.size(); ++k) {
        EXPECT_FALSE(chord.entries[k].IsEdgePoint());
      }
      for (size_t k = 1; k < chord.entries.size(); ++k) {
        EXPECT_LE(chord.entries[k - 1].along, chord.entries[k].along);
      }
    }
  }
}

}  // namespace
}  // namespace surfdeform::subdivision
