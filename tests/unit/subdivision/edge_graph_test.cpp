// Subdivision stage: the welded edge graph.
#include "engine/subdivision/edge_graph.hpp"

#include <gtest/gtest.h>

#include "stage_test_util.hpp"

namespace surfdeform::subdivision {
namespace {

// Every non-degenerate face's edge k joins its corners k and k + 1 (by
// welded id), in the direction `reversed` says, and lists the face.
void ExpectConsistent(const EdgeGraph& g) {
  for (size_t f = 0; f < g.faces.size(); ++f) {
    const GraphFace& face = g.faces[FaceId(f)];
    if (face.degenerate) continue;
    for (int k = 0; k < 3; ++k) {
      const GraphEdge& e = g.edges[face.edge[k]];
      WeldedId a = g.weld[face.corner[k]], b = g.weld[face.corner[(k + 1) % 3]];
      if (face.reversed[k]) std::swap(a, b);
      EXPECT_EQ(a, e.w0) << f << " " << k;
      EXPECT_EQ(b, e.w1) << f << " " << k;
      EXPECT_LT(e.w0, e.w1);
      EXPECT_EQ(g.weld[e.v0], e.w0);
      EXPECT_EQ(g.weld[e.v1], e.w1);
      bool listed = false;
      for (const FaceId* q = g.FacesBegin(face.edge[k]); q != g.FacesEnd(face.edge[k]); ++q) {
        listed = listed || *q == FaceId(f);
      }
      EXPECT_TRUE(listed) << f << " " << k;
    }
  }
}

TEST(EdgeGraph, AClosedPlateHasThreeHalvesOfItsFacesAsEdgesEachWithTwoFaces) {
  const EdgeGraph g = BuildEdgeGraph(testing::ThinPlate(2, 1, 0.1));
  ASSERT_EQ(g.faces.size(), 12u);
  EXPECT_EQ(g.edges.size(), 18u);
  for (size_t e = 0; e < g.edges.size(); ++e) {
    EXPECT_EQ(g.FacesEnd(EdgeId(e)) - g.FacesBegin(EdgeId(e)), 2) << e;
  }
  ExpectConsistent(g);
}

TEST(EdgeGraph, VerticesAtOnePositionAreWeldedToTheSmallestIndexAndShareEdges) {
  const Mesh seams = testing::Unwelded(testing::ThinPlate(2, 1, 0.1));
  const EdgeGraph g = BuildEdgeGraph(seams);
  ASSERT_EQ(g.weld.size(), 36u);
  for (size_t v = 0; v < 36; ++v) {
    const WeldedId w = g.weld[VertexId(v)];
    EXPECT_LE(w.value(), v);
    EXPECT_EQ(seams.positions[w.value()], seams.positions[v]);
    for (size_t u = 0; u < w.value(); ++u) EXPECT_NE(seams.positions[u], seams.positions[v]);
  }
  EXPECT_EQ(g.edges.size(), 18u);  // as the welded plate's: seams do not open
  ExpectConsistent(g);
}

TEST(EdgeGraph, AFaceWithTwoCornersAtOnePositionIsDegenerateAndHasNoEdges) {
  Mesh m = testing::ThinPlate(2, 1, 0.1);
  m.positions.push_back(m.positions[0]);  // vertex 8 at vertex 0's position
  m.triangles.push_back({0, 8, 3});
  const EdgeGraph g = BuildEdgeGraph(m);
  EXPECT_TRUE(g.faces[FaceId(12u)].degenerate);
  EXPECT_EQ(g.edges.size(), 18u);
  for (size_t f = 0; f < 12; ++f) EXPECT_FALSE(g.faces[FaceId(f)].degenerate);
  ExpectConsistent(g);
}

TEST(EdgeGraph, FacesOfAnEdgeAreListedByFaceOrder) {
  const EdgeGraph g = BuildEdgeGraph(testing::FlatGrid(0, 0, 1, 1, 5, 4, 0));
  EXPECT_EQ(g.edges.size(),
            static_cast<size_t>(5 * 5 + 4 * 6 + 5 * 4));  // rows, columns, diagonals
  for (size_t e = 0; e < g.edges.size(); ++e) {
    for (const FaceId* q = g.FacesBegin(EdgeId(e)); q + 1 < g.FacesEnd(EdgeId(e)); ++q) {
      EXPECT_LT(*q, *(q + 1));
    }
  }
  ExpectConsistent(g);
}

}  // namespace
}  // namespace surfdeform::subdivision
