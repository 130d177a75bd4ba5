// Surface distances d_ij against closed forms.
#include "engine/distance/surface_distance.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/surface/surface_spec.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

std::unique_ptr<Surface> Make(const SurfaceSpec& spec) { return testing::MakeValid(spec); }

// Worst relative difference between d_ij and the distance of the exact
// unrolled positions.
double WorstAgainstUnrolling(const Surface& s, const SurfaceDistances& d) {
  double worst = 0.0;
  for (const GridEdge& e : d.edges) {
    const int i0 = e.i % d.nu, j0 = e.i / d.nu, i1 = e.j % d.nu, j1 = e.j / d.nu;
    const Vec2 a = *s.ExactUnrolling(i0 / (d.nu - 1.0), j0 / (d.nv - 1.0));
    const Vec2 b = *s.ExactUnrolling(i1 / (d.nu - 1.0), j1 / (d.nv - 1.0));
    worst = std::max(worst, std::abs(e.d - (a - b).norm()) / (a - b).norm());
  }
  return worst;
}

TEST(SurfaceDistance, EveryPairWithinRangeOnce) {
  auto s = Make(WaveSpec{});
  DistanceOptions o;
  o.range = 2;
  auto d = ComputeSurfaceDistances(*s, 7, 5, o);
  ASSERT_TRUE(d.ok());
  // Pairs within Chebyshev range 2 on a 7x5 grid, counted directly.
  size_t expected = 0;
  for (int a = 0; a < 35; ++a)
    for (int b = a + 1; b < 35; ++b)
      if (std::abs(a % 7 - b % 7) <= 2 && std::abs(a / 7 - b / 7) <= 2) ++expected;
  EXPECT_EQ(d->edges.size(), expected);
  for (const GridEdge& e : d->edges) {
    EXPECT_LT(e.i, e.j);
    EXPECT_EQ(e.j - e.i, e.di + 7 * e.dj);
    EXPECT_EQ(e.ring, std::max(std::abs(e.di), std::abs(e.dj)));
  }
}

TEST(SurfaceDistance, PlaneDistancesAreEuclidean) {
  BezierSpec b;  // a planar patch with an uneven parameterisation
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) b.control_points.emplace_back(i * i / 3.0 + 0.2 * j, j * 0.8, 0);
  auto s = Make(b);
  auto d = ComputeSurfaceDistances(*s, 9, 9, {});
  ASSERT_TRUE(d.ok());
  for (const GridEdge& e : d->edges) {
    const Vec3 pi = s->Position((e.i % 9) / 8.0, (e.i / 9) / 8.0);
    const Vec3 pj = s->Position((e.j % 9) / 8.0, (e.j / 9) / 8.0);
    EXPECT_NEAR(e.d, (pi - pj).norm(), 1e-6 * (pi - pj).norm());
  }
}

TEST(SurfaceDistance, CylinderDistancesAreExact) {
  auto s = Make(CylinderSpec{1.0, 2.0, 240.0, {}});
  auto d = ComputeSurfaceDistances(*s, 16, 16, {});
  ASSERT_TRUE(d.ok());
  EXPECT_LT(WorstAgainstUnrolling(*s, *d), 1e-6);
  EXPECT_EQ(d->relaxed_paths, 0);  // helices are geodesics already
}

TEST(SurfaceDistance, ConeDistancesAreGeodesicNotStraightSegments) {
  auto s = Make(ConeSpec{1.0, 0.5, 1.0, 240.0, {}});
  DistanceOptions straight;
  straight.relax_steps = 0;
  auto d0 = ComputeSurfaceDistances(*s, 16, 16, straight);
  auto d1 = ComputeSurfaceDistances(*s, 16, 16, {});
  ASSERT_TRUE(d0.ok() && d1.ok());
  // The straight parameter segment overestimates by ~1e-2; the relaxed path
  // matches the unrolled (exact geodesic) distance.
  EXPECT_GT(WorstAgainstUnrolling(*s, *d0), 1e-3);
  EXPECT_LT(WorstAgainstUnrolling(*s, *d1), 1e-5);
  EXPECT_GT(d1->relaxed_paths, 0);
}

TEST(SurfaceDistance, ResultDoesNotDependOnThreadCount) {
  auto s = Make(TorusSpec{});
  DistanceOptions one, two;
  one.threads = 1;
  two.threads = 2;
  auto a = ComputeSurfaceDistances(*s, 23, 17, one);
  auto b = ComputeSurfaceDistances(*s, 23, 17, two);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a->edges.size(), b->edges.size());
  for (size_t k = 0; k < a->edges.size(); ++k) {
    EXPECT_EQ(a->edges[k].i, b->edges[k].i);
    EXPECT_EQ(a->edges[k].d, b->edges[k].d);  // bit for bit
  }
}

TEST(SurfaceDistance, CellAreasSumToTheSurfaceArea) {
  auto s = Make(SphereSpec{2.0, 0, 90, 0, 60, {}});
  auto d = ComputeSurfaceDistances(*s, 12, 12, {});
  ASSERT_TRUE(d.ok());
  double sum = 0;
  for (double a : d->cell_areas) sum += a;
  // Zone of a sphere: 2 pi R^2 (sin(lat1) - sin(lat0)) over a quarter of longitude.
  const double exact = 0.25 * 2 * M_PI * 4.0 * std::sin(M_PI / 3);
  EXPECT_NEAR(sum, exact, 2e-3 * exact);
}

TEST(SurfaceDistance, RejectsRangeOutOfBounds) {
  auto s = Make(WaveSpec{});
  DistanceOptions o;
  o.range = 9;
  auto d = ComputeSurfaceDistances(*s, 8, 8, o);
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.status().field(), "range");
}

// Measured along its own paths, a surface gives its own distances: the relaxed
// paths' lengths are taken the same way in both.
TEST(SurfaceDistance, RemeasuredAlongItsOwnPathsGivesItsDistances) {
  auto s = Make(ConeSpec{1.0, 0.5, 1.0, 240.0, {}});
  DistancePaths paths;
  auto fresh = ComputeSurfaceDistances(*s, 16, 16, {}, &paths);
  ASSERT_TRUE(fresh.ok());
  const WeightedPaths own[] = {{&paths, 1.0}};
  const PathBlend blends[] = {PathBlend(own)};
  auto again = RemeasureSurfaceDistances(*s, blends, {});
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  ASSERT_EQ(again->edges.size(), fresh->edges.size());
  EXPECT_GT(again->reused_paths, 0);
  EXPECT_EQ(again->relaxed_paths, 0);
  for (size_t k = 0; k < fresh->edges.size(); ++k) {
    EXPECT_NEAR(again->edges[k].d, fresh->edges[k].d, 1e-13 * fresh->edges[k].d) << k;
  }
  EXPECT_EQ(again->cell_areas, fresh->cell_areas);
}

// Helices are geodesics on every cylinder: the paths followed on one measure
// another of a different radius exactly.
TEST(SurfaceDistance, CylinderPathsMeasureAnotherCylinderExactly) {
  auto thin = Make(CylinderSpec{1.0, 2.0, 240.0, {}});
  auto wide = Make(CylinderSpec{1.3, 2.0, 240.0, {}});
  DistancePaths paths;
  ASSERT_TRUE(ComputeSurfaceDistances(*thin, 16, 16, {}, &paths).ok());
  const WeightedPaths w[] = {{&paths, 1.0}};
  const PathBlend blends[] = {PathBlend(w)};
  auto d = RemeasureSurfaceDistances(*wide, blends, {});
  ASSERT_TRUE(d.ok());
  EXPECT_GT(d->reused_paths, 0);
  EXPECT_LT(WorstAgainstUnrolling(*wide, *d), 1e-6);
}

// A cone between two others, measured along the blend of their relaxed
// paths (none relaxed again), matches its exact geodesic distances as closely
// as a fresh measurement does.
TEST(SurfaceDistance, BlendedPathsMeasureTheConeBetween) {
  auto narrow = Make(ConeSpec{1.0, 0.5, 1.0, 240.0, {}});
  auto middle = Make(ConeSpec{1.0, 0.55, 1.0, 240.0, {}});
  auto wide = Make(ConeSpec{1.0, 0.6, 1.0, 240.0, {}});
  DistancePaths a, b;
  ASSERT_TRUE(ComputeSurfaceDistances(*narrow, 16, 16, {}, &a).ok());
  ASSERT_TRUE(ComputeSurfaceDistances(*wide, 16, 16, {}, &b).ok());
  const WeightedPaths w[] = {{&a, 0.5}, {&b, 0.5}};
  const PathBlend blends[] = {PathBlend(w)};
  auto d = RemeasureSurfaceDistances(*middle, blends, {});
  auto fresh = ComputeSurfaceDistances(*middle, 16, 16, {});
  ASSERT_TRUE(d.ok() && fresh.ok());
  EXPECT_GT(d->reused_paths, 1000);
  EXPECT_EQ(d->relaxed_paths, 0);
  // Measured: 5.9e-7 blended, 8.8e-7 fresh; 1.1e-6 apart at most.
  EXPECT_LT(WorstAgainstUnrolling(*middle, *d), 1e-6);
  EXPECT_LT(WorstAgainstUnrolling(*middle, *fresh), 1e-6);
  double apart = 0.0;
  for (size_t k = 0; k < d->edges.size(); ++k) {
    apart = std::max(apart, std::abs(d->edges[k].d - fresh->edges[k].d) / fresh->edges[k].d);
  }
  EXPECT_LT(apart, 2e-6);
}

TEST(SurfaceDistance, RemeasureRejectsForeignOrUnbalancedPaths) {
  auto s = Make(WaveSpec{});
  DistancePaths paths;
  ASSERT_TRUE(ComputeSurfaceDistances(*s, 8, 8, {}, &paths).ok());
  const WeightedPaths unbalanced[] = {{&paths, 0.7}};
  const PathBlend b1[] = {PathBlend(unbalanced)};
  EXPECT_EQ(RemeasureSurfaceDistances(*s, b1, {}).status().code(), ErrorCode::kInvalidArgument);
  const WeightedPaths own[] = {{&paths, 1.0}};
  const PathBlend b2[] = {PathBlend(own)};
  DistanceOptions other_range;
  other_range.range = 2;
  EXPECT_EQ(RemeasureSurfaceDistances(*s, b2, other_range).status().code(),
            ErrorCode::kInvalidArgument);
  EXPECT_EQ(RemeasureSurfaceDistances(*s, {}, {}).status().code(), ErrorCode::kInvalidArgument);
}

// An edit measured from the previous edit's paths (RefollowSurfaceDistances),
// edit after edit: cones opening step by step keep matching their exact
// geodesic distances as closely as a fresh measurement does, and each hands
// its paths on.
TEST(SurfaceDistance, RefollowedEditAfterEditMatchesTheExactGeodesics) {
  DistancePaths paths;
  auto first = Make(ConeSpec{1.0, 0.5, 1.0, 240.0, {}});
  ASSERT_TRUE(ComputeSurfaceDistances(*first, 16, 16, {}, &paths).ok());
  for (double top : {0.52, 0.55, 0.6, 0.7}) {
    auto cone = Make(ConeSpec{1.0, top, 1.0, 240.0, {}});
    DistancePaths next;
    auto d = RefollowSurfaceDistances(*cone, paths, {}, &next);
    ASSERT_TRUE(d.ok()) << d.status().ToString();
    auto fresh = ComputeSurfaceDistances(*cone, 16, 16, {});
    ASSERT_TRUE(fresh.ok());
    EXPECT_GT(d->reused_paths, 1000) << top;
    // Measured: 1.02e-6 refollowed and 8.8e-7 fresh at the first edit.
    EXPECT_LT(WorstAgainstUnrolling(*cone, *d), 1.5e-6) << top;
    EXPECT_LT(WorstAgainstUnrolling(*cone, *fresh), 1.5e-6) << top;
    ASSERT_EQ(next.turn.size(), d->edges.size());
    paths = std::move(next);
  }
}

// Refollowing its own paths on the same surface: the distances of the
// measurement that followed them, or shorter (a step from exact evaluations
// goes on where the relaxation stopped: by up to 1.1e-7 here).
TEST(SurfaceDistance, RefollowedOnTheSameSurfaceGivesItsDistances) {
  auto s = Make(WaveSpec{});
  DistancePaths paths;
  auto fresh = ComputeSurfaceDistances(*s, 16, 16, {}, &paths);
  auto again = RefollowSurfaceDistances(*s, paths, {});
  ASSERT_TRUE(fresh.ok() && again.ok());
  EXPECT_GT(again->reused_paths, 0);
  for (size_t k = 0; k < fresh->edges.size(); ++k) {
    EXPECT_NEAR(again->edges[k].d, fresh->edges[k].d, 1e-6 * fresh->edges[k].d) << k;
    EXPECT_LE(again->edges[k].d, fresh->edges[k].d * (1.0 + 1e-12)) << k;
  }
}

TEST(SurfaceDistance, RefollowRejectsPathsOfAnotherGridOrRange) {
  auto s = Make(WaveSpec{});
  DistancePaths paths;
  ASSERT_TRUE(ComputeSurfaceDistances(*s, 8, 8, {}, &paths).ok());
  DistanceOptions other_range;
  other_range.range = 2;
  EXPECT_EQ(RefollowSurfaceDistances(*s, paths, other_range).status().code(),
            ErrorCode::kInvalidArgument);
  DistanceOptions other_lattice;
  other_lattice.lattice_factor = 2;
  EXPECT_EQ(RefollowSurfaceDistances(*s, paths, other_lattice).status().code(),
            ErrorCode::kInvalidArgument);
  DistancePaths cut = paths;
  cut.q.pop_back();
  EXPECT_EQ(RefollowSurfaceDistances(*s, cut, {}).status().code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace surfdeform
