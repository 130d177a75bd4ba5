// The constrained Delaunay triangulation of one face.
#include "engine/subdivision/face_triangulation.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <tuple>

namespace surfdeform {
namespace {

// Every triangle counter-clockwise, the areas summing to the face's, every
// interior edge shared by exactly two triangles in opposite directions.
void ExpectValid(const FaceTriangulation& tri, double face_area) {
  const auto& pts = tri.points();
  double area = 0.0;
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : tri.triangles()) {
    const double a = 0.5 * Cross2(pts[t.v[1]] - pts[t.v[0]], pts[t.v[2]] - pts[t.v[0]]);
    EXPECT_GT(a, 0.0);
    area += a;
    for (int k = 0; k < 3; ++k) ++edges[{t.v[k], t.v[(k + 1) % 3]}];
  }
  EXPECT_NEAR(area, face_area, 1e-12 * face_area);
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1);
  }
}

bool HasEdge(const FaceTriangulation& tri, int a, int b) {
  for (const auto& t : tri.triangles()) {
    for (int k = 0; k < 3; ++k) {
      if (t.v[k] == a && t.v[(k + 1) % 3] == b) return true;
    }
  }
  return false;
}

TEST(FaceTriangulation, SidePointsAndInteriorPointsGiveAValidTriangulation) {
  FaceTriangulation tri(Vec2(0, 0), Vec2(4, 0), Vec2(0, 3));
  int prev = 0;
  for (int q = 1; q < 8; ++q) prev = tri.SplitBoundary(prev, 1, Vec2(0.5 * q, 0));
  EXPECT_EQ(tri.points().size(), 10u);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int q = 0; q < 200; ++q) {
    double a = u(rng), b = u(rng);
    if (a + b > 1) {
      a = 1 - a;
      b = 1 - b;
    }
    EXPECT_GE(tri.Insert(Vec2(4 * a, 3 * b)), 0);
  }
  ExpectValid(tri, 6.0);
  // Sides stay as given: each side point is joined to its neighbours.
  for (int q = 3; q < 9; ++q) EXPECT_TRUE(HasEdge(tri, q, q + 1)) << q;
  EXPECT_EQ(tri.Insert(Vec2(5, 5)), -1);        // outside
  EXPECT_EQ(tri.Insert(Vec2(2.25, 0)), -1);     // on a side: sides are fixed
  EXPECT_EQ(tri.Insert(Vec2(2, 0)), 6);         // a side point
  EXPECT_EQ(tri.Insert(tri.points()[20]), 20);  // an existing point
}

TEST(FaceTriangulation, ConstraintsBecomeEdgesAndSurviveDelaunayFlips) {
  // A row of interior points, constrained along a line that Delaunay alone
  // would cut across (the points above and below are much closer).
  FaceTriangulation tri(Vec2(0, 0), Vec2(10, 0), Vec2(5, 10));
  std::vector<int> row;
  for (int q = 0; q < 5; ++q) row.push_back(tri.Insert(Vec2(3 + q, 2.0 + 0.01 * (q % 2))));
  for (int q = 0; q < 4; ++q) {
    tri.Insert(Vec2(3.5 + q, 2.3));
    tri.Insert(Vec2(3.5 + q, 1.7));
  }
  for (int q = 0; q + 1 < 5; ++q) EXPECT_TRUE(tri.Constrain(row[q], row[q + 1]));
  tri.RestoreDelaunay();
  for (int q = 0; q + 1 < 5; ++q) {
    EXPECT_TRUE(HasEdge(tri, row[q], row[q + 1]) || HasEdge(tri, row[q + 1], row[q])) << q;
  }
  ExpectValid(tri, 50.0);
  // A constraint from a corner to a far point, crossing many edges.
  EXPECT_TRUE(tri.Constrain(0, row[4]));
  EXPECT_TRUE(HasEdge(tri, 0, row[4]) || HasEdge(tri, row[4], 0));
  ExpectValid(tri, 50.0);
}

// A constraint across a band of 2,000 edges between two rows of points: the
// stop test (SetStop) is looked at as it flips, and a true one gives up
// (the request's time budget, on a long thin face where this took minutes
// under ASan); without one, or with a false one, the constraint is made.
TEST(FaceTriangulation, AConstraintGivesUpWhenTheStopTestSaysSo) {
  auto band = [] {
    FaceTriangulation tri(Vec2(0, 0), Vec2(1, 0), Vec2(0, 1));
    const int a = tri.Insert(Vec2(0.005, 0.4));
    for (int q = 0; q < 1000; ++q) {
      const double x = 0.01 + 0.0005 * q;
      tri.Insert(Vec2(x, 0.38));
      tri.Insert(Vec2(x + 0.00025, 0.42));
    }
    const int b = tri.Insert(Vec2(0.55, 0.4));
    return std::make_tuple(std::move(tri), a, b);
  };
  {
    auto [tri, a, b] = band();
    EXPECT_TRUE(tri.Constrain(a, b));
    EXPECT_TRUE(HasEdge(tri, a, b) || HasEdge(tri, b, a));
    ExpectValid(tri, 0.5);
  }
  {
    auto [tri, a, b] = band();
    int asked = 0;
    tri.SetStop([&] { return ++asked < 0; });  // never
    EXPECT_TRUE(tri.Constrain(a, b));
    EXPECT_GT(asked, 0);  // it was looked at
  }
  {
    auto [tri, a, b] = band();
    tri.SetStop([] { return true; });
    EXPECT_FALSE(tri.Constrain(a, b));
    ExpectValid(tri, 0.5);  // the flips made so far leave it valid
  }
}

TEST(FaceTriangulation, InteriorEdgeSplitsKeepItValid) {
  FaceTriangulation tri(Vec2(0, 0), Vec2(1, 0), Vec2(0, 1));
  tri.Insert(Vec2(0.25, 0.25));
  for (int round = 0; round < 50; ++round) {
    // Split the longest interior edge of the first triangle that has one.
    for (size_t t = 0; t < tri.triangles().size(); ++t) {
      int k = -1;
      for (int q = 0; q < 3; ++q) {
        if (!tri.OnOutline(static_cast<int>(t), q)) k = q;
      }
      if (k >= 0) {
        EXPECT_GT(tri.SplitInteriorEdge(static_cast<int>(t), k), 0);
        break;
      }
    }
  }
  ExpectValid(tri, 0.5);
  EXPECT_EQ(tri.points().size(), 54u);
}

}  // namespace
}  // namespace surfdeform

namespace surfdeform {
namespace {

// A side of a thin plate: a triangle 50 times longer than high, with points on
// its long sides (as grid lines cross them), stays a valid triangulation.
TEST(FaceTriangulation, ElongatedFacesWithManySidePointsStayValid) {
  for (double height : {0.18, 0.01, 1e-4}) {
    FaceTriangulation tri(Vec2(0, 0), Vec2(9, 0), Vec2(9, height));
    int prev = 0;
    for (int q = 1; q < 9; ++q) prev = tri.SplitBoundary(prev, 1, Vec2(q + 0.1 * (q % 3), 0));
    prev = 2;
    for (int q = 8; q >= 1; --q) {
      const double x = q + 0.1 * (q % 3);
      prev = tri.SplitBoundary(prev, 0, Vec2(x, height * x / 9));
      ASSERT_GE(prev, 0);
    }
    ExpectValid(tri, 4.5 * height);
  }
}

}  // namespace
}  // namespace surfdeform
