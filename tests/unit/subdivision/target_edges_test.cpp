// Subdivision on a surface given as a mesh (section 3): the
// target's edges take the grid's part, so the edge points are where the
// model's edges cross them and the face points its vertices inside the
// model's faces.
#include "engine/subdivision/target_edges.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "engine/common/disk_mesh.hpp"
#include "engine/surface/mesh_surface.hpp"
#include "support/mesh_soup.hpp"
#include "support/subdivision_check.hpp"
#include "support/test_meshes.hpp"

namespace surfdeform::subdivision {
namespace {

using testing::Soup;

// `soup` as a flat mesh whose flat positions are its x and y (the 3D
// positions as given): enough for the index, which reads the flat layout
// and the 3D triangles.
FlatMesh Layout(const Soup& soup) {
  auto disk = MakeDiskMesh(soup.positions, soup.triangles);
  EXPECT_TRUE(disk.ok()) << disk.status().ToString();
  FlatMesh m;
  if (!disk.ok()) return m;
  m.mesh = std::move(*disk);
  for (const Vec3& p : m.mesh.positions) m.flat.push_back(p.head<2>());
  return m;
}

// The crossings of segment a-b with every edge of `m`, by brute force: t
// along a-b of each proper crossing.
std::vector<double> BruteCrossings(const FlatMesh& m, const Vec2& a, const Vec2& b) {
  std::vector<double> ts;
  const auto& tris = m.mesh.triangles;
  for (size_t f = 0; f < tris.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int u = m.mesh.neighbours[f][k];
      if (u >= 0 && u < static_cast<int>(f)) continue;
      const Vec2 p = m.flat[tris[f][k]], q = m.flat[tris[f][(k + 1) % 3]];
      const double den = Cross2(b - a, q - p);
      if (std::abs(den) < 1e-15) continue;
      const double t = Cross2(p - a, q - p) / den, s = Cross2(p - a, b - a) / den;
      if (t > 1e-7 && t < 1 - 1e-7 && s >= 0 && s <= 1) ts.push_back(t);
    }
  }
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end(), [](double x, double y) { return y - x <= 1e-9; }),
           ts.end());
  return ts;
}

TEST(TargetEdges, FindsTheCrossingsAndTheVerticesInsideThatABruteSearchFinds) {
  const Soup soup = testing::Grid(
      9, 7, 0.3, 5, [](double s, double t) { return Vec3(3.0 * s, 2.0 * t, 0.1 * s * t); });
  const FlatMesh m = Layout(soup);
  const TargetEdges target(m, Eigen::Matrix2d::Identity(), Vec2::Zero());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-0.2, 3.2), y(-0.2, 2.2);
  std::vector<GridCrossing> crossings;
  std::vector<GridNodeInside> inside;
  std::vector<int> scratch;
  int crossed = 0, held = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Vec2 a(x(rng), y(rng)), b(x(rng), y(rng));
    const Vec2 c(x(rng), y(rng));
    // Also along the axes and the buckets' diagonals, through their corners.
    if (trial % 3 == 1) b.y() = a.y();
    if (trial % 6 == 2) b.x() = a.x();
    if (trial % 6 == 5) {
      a = Vec2(0.0, 0.0);
      b = Vec2(3.0, 2.0) * (0.5 + trial / 600.0);
    }
    double shortest;
    target.Crossings(a, b, &crossings, &shortest, &scratch);
    const std::vector<double> expected = BruteCrossings(m, a, b);
    ASSERT_EQ(crossings.size(), expected.size()) << trial;
    for (size_t k = 0; k < expected.size(); ++k) {
      EXPECT_NEAR(crossings[k].t, expected[k], 1e-12);
      // On the edge it names, at the fraction it says.
      const TargetEdges::Edge& e = target.edges()[crossings[k].u_line];
      const Vec2 on_edge =
          m.flat[e.v[0]] + crossings[k].u_along * (m.flat[e.v[1]] - m.flat[e.v[0]]);
      EXPECT_LT((on_edge - (a + crossings[k].t * (b - a))).norm(), 1e-12);
      EXPECT_GE(shortest, 0.0);
      EXPECT_LE(shortest, e.length);
    }
    crossed += static_cast<int>(expected.size());
    target.VerticesInside(a, b, c, &inside);
    int count = 0;
    const double det = Cross2(b - a, c - a);
    for (size_t v = 0; v < m.flat.size(); ++v) {
      const Vec2 p = m.flat[v] - a;
      const double l1 = Cross2(p, c - a) / det, l2 = Cross2(b - a, p) / det;
      count += l1 > 1e-7 && l2 > 1e-7 && 1 - l1 - l2 > 1e-7;
    }
    ASSERT_EQ(static_cast<int>(inside.size()), count) << trial;
    for (const GridNodeInside& n : inside) {
      EXPECT_LT((a + n.l1 * (b - a) + n.l2 * (c - a) - m.flat[n.i]).norm(), 1e-12);
    }
    held += count;
  }
  EXPECT_GT(crossed, 500);
  EXPECT_GT(held, 100);
}

TEST(TargetEdges, AnEdgeKinksByTheJumpOfTheMapsDerivativeAcrossIt) {
  // z = 0.5 |x - 1| folds the plane along x = 1: the map's derivative
  // across the fold goes from (1, 0, -0.5) to (1, 0, 0.5).
  const Soup soup = testing::Grid(5, 3, 0.0, 1, [](double s, double t) {
    return Vec3(2.0 * s, t, 0.5 * std::abs(2.0 * s - 1));
  });
  const FlatMesh m = Layout(soup);
  const TargetEdges target(m, Eigen::Matrix2d::Identity(), Vec2::Zero());
  int on_fold = 0;
  for (const TargetEdges::Edge& e : target.edges()) {
    const Vec2 p = m.flat[e.v[0]], q = m.flat[e.v[1]];
    if (std::abs(p.x() - 1) < 1e-12 && std::abs(q.x() - 1) < 1e-12) {
      EXPECT_NEAR(e.kink, 1.0, 1e-12);
      ++on_fold;
    } else {
      EXPECT_LT(e.kink, 1e-12);
    }
  }
  EXPECT_EQ(on_fold, 2);
}

// A mesh surface target from `soup`, flattened, and sampled for the sheet.
testing::Target MeshTarget(const Soup& soup) {
  testing::Target t;
  auto disk = MakeDiskMesh(soup.positions, soup.triangles);
  EXPECT_TRUE(disk.ok()) << disk.status().ToString();
  auto flat = FlattenMesh(std::move(*disk), {});
  EXPECT_TRUE(flat.ok()) << flat.status().ToString();
  t.surface = std::make_unique<MeshSurface>(std::make_shared<const FlatMesh>(std::move(*flat)));
  auto sheet = FlattenSurface(*t.surface, SamplingOptions{33, 33});
  EXPECT_TRUE(sheet.ok()) << sheet.status().ToString();
  t.sheet = std::move(*sheet);
  return t;
}

// The distance from p to the nearest edge of `soup`'s triangles.
double DistanceToAnEdge(const Soup& soup, const Vec3& p) {
  double best = 1e300;
  for (const auto& t : soup.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = soup.positions[t[k]], b = soup.positions[t[(k + 1) % 3]];
      const double s = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + s * (b - a) - p).norm());
    }
  }
  return best;
}

// A layer of triangles across one fold of a plane (z = 0.5 |x|): the map is
// flat on each triangle, so the layer cut where its edges cross the edges
// that kink deforms exactly, and every vertex added lies on an edge of the
// mesh, most on the fold (the others where the flattening's own small
// distortion kinks the map past what the tolerance allows). Before, the
// refinement bisected towards the fold until each piece met the tolerance:
// points beside it, never on it.
TEST(TargetEdges, ALayerAcrossAFoldIsCutExactlyAlongIt) {
  // The fold at a third of the width (the third of 7 columns): no line of
  // the sheet's 33 x 33 grid runs along it.
  const Soup soup = testing::Grid(7, 5, 0.0, 1, [](double s, double t) {
    return Vec3(3.0 * s - 1.0, 2.0 * t, 0.5 * std::abs(3.0 * s - 1.0));
  });
  const testing::Target target = MeshTarget(soup);
  // Centred on the sheet's centre, 0.56 past the fold: its columns at -1,
  // -0.6, ... from there, none on the fold.
  const Mesh layer = testing::FlatGrid(-1.0, -0.6, 2.0, 1.2, 5, 4, 0.0);
  PlacementOptions flat;  // heights as given: the layer on the surface
  flat.anchor = AnchorMode::kValue;
  SubdivisionOptions s;
  s.tolerance = 1e-4;
  const testing::Refined r = testing::Refine(target, layer, flat, s);
  ASSERT_TRUE(r.ok);
  int on_fold = 0;
  for (size_t v = layer.positions.size(); v < r.deformed.size(); ++v) {
    EXPECT_LT(DistanceToAnEdge(soup, r.deformed[v]), 1e-9) << v;
    on_fold += std::abs(r.deformed[v].x()) < 1e-9;
  }
  // The layer's 5 rows of edges cross the fold (5 points), its 4 rows of
  // diagonals too (4), and the fold's vertices at y = 0.5 and 1.0 fall
  // inside its faces (2).
  EXPECT_EQ(on_fold, 11);
  EXPECT_LT(testing::DenseDeviation(target, r, OutsideMode::kError), 1e-9);
  EXPECT_EQ(r.stats.refinement_points, 0u);
}

// The paper's thin plate along half a cylinder of 12 flat facets: within
// the tolerance, watertight, with the points the kinks need. Bisecting
// towards the kinks instead added 17,364 vertices at 1e-4 and strayed by
// 1.27e-4 (dense), 1.05e-3 at 1e-3.
TEST(TargetEdges, APlateAlongAFacetedCylinderMeetsTheToleranceWithFewPoints) {
  const Soup soup = testing::Grid(13, 7, 0.0, 1, [](double s, double t) {
    const double a = std::numbers::pi * s;
    return Vec3(std::cos(a), std::sin(a), 2.0 * t);
  });
  const testing::Target target = MeshTarget(soup);
  const Mesh plate = testing::ThinPlate(2.0, 1.0, 0.1);
  PlacementOptions fit;
  fit.fit = true;
  for (double tolerance : {1e-3, 1e-4}) {
    SubdivisionOptions s;
    s.tolerance = tolerance;
    const testing::Refined r = testing::Refine(target, plate, fit, s);
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(testing::ClosedManifoldProblem(r.model), "") << tolerance;
    EXPECT_LE(testing::DenseDeviation(target, r, OutsideMode::kError), tolerance) << tolerance;
    EXPECT_GT(r.stats.edge_points_kept, 0u);
    EXPECT_LT(r.model.positions.size(), tolerance < 5e-4 ? 8000u : 1000u) << tolerance;
  }
}

// The paper's threshold alone (epsilon, a curvature, no tolerance): a mesh
// bends only at its edges, by its kink over the crossed edge's length there:
// half a cylinder of 12 facets 1/3 tall bends by 0.26 / (1/3) = 0.78 at each
// vertical edge, and nowhere else.
TEST(TargetEdges, EpsilonKeepsTheCrossingsOfEdgesThatBendMoreThanIt) {
  const Soup soup = testing::Grid(13, 7, 0.0, 1, [](double s, double t) {
    const double a = std::numbers::pi * s;
    return Vec3(std::cos(a), std::sin(a), 2.0 * t);
  });
  const testing::Target target = MeshTarget(soup);
  // A strip of triangles on the surface (heights 0), across several facets.
  const Mesh plate = testing::FlatGrid(-1.0, 0.05, 2.0, 0.2, 6, 1, 0.0);
  PlacementOptions fit;
  fit.anchor = AnchorMode::kValue;
  for (double epsilon : {0.5, 1.0}) {
    SubdivisionOptions s;
    s.epsilon = epsilon;
    const testing::Refined r = testing::Refine(target, plate, fit, s);
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.stats.refinement_points, 0u);
    if (epsilon < 0.78) {
      EXPECT_GT(r.stats.edge_points_kept, 10u);
      // Every point added is on one of the mesh's edges on the sheet.
      const TargetEdges edges(*target.surface->flat_mesh(), target.sheet.frame_linear,
                              target.sheet.frame_offset);
      std::vector<GridCrossing> none;
      std::vector<int> scratch;
      for (size_t v = plate.positions.size(); v < r.placed.size(); ++v) {
        const Vec2 p = r.placed[v].head<2>();
        // A hair across p, along x or along y, crosses an edge through p.
        double shortest;
        const Vec2 dx(1e-9, 0.0), dy(0.0, 1e-9);
        edges.Crossings(p - dx, p + dx, &none, &shortest, &scratch);
        const bool along_x = !none.empty();
        edges.Crossings(p - dy, p + dy, &none, &shortest, &scratch);
        EXPECT_TRUE(along_x || !none.empty()) << v << ": " << p.transpose();
      }
    } else {
      EXPECT_EQ(r.model.positions.size(), plate.positions.size());
    }
  }
}

}  // namespace
}  // namespace surfdeform::subdivision
