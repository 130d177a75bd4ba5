// Subdivision: the paper's edge and face points, the tolerance, conformity.
#include "engine/subdivision/subdivide.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <numbers>
#include <random>

#include "engine/deform/deform.hpp"
#include "engine/placement/placement.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/surface/surface_spec.hpp"
#include "support/subdivision_check.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

using testing::Flattened;
using testing::Target;

Target Figure(int number, int n) {
  return Flattened(
      testing::LoadBezierFile(testing::DataPath("figure" + std::to_string(number) + ".json")), n);
}

BezierSpec Plane() {  // the square [0, 2]^2 at z = 0
  BezierSpec plane;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) plane.control_points.emplace_back(2.0 * i / 3, 2.0 * j / 3, 0.0);
  return plane;
}

using testing::DenseDeviation;
using testing::Refine;
using testing::Refined;

PlacementOptions Fit() {
  PlacementOptions o;
  o.fit = true;
  o.fit_margin = 0.05;
  return o;
}

SubdivisionOptions Adaptive(double tolerance) {
  SubdivisionOptions s;
  s.tolerance = tolerance;
  return s;
}

// Positions of the refined model that the input did not have.
size_t Added(const Refined& r, const Mesh& input) {
  return r.model.positions.size() - input.positions.size();
}

TEST(Subdivide, ThinPlateOnACylinderStaysWithinTheToleranceAndWatertight) {
  const Target t = Flattened(CylinderSpec{1.0, 2.0, 180.0, {}}, 16);
  const Mesh plate = testing::ThinPlate(2.6, 1.6, 0.1);
  for (double tolerance : {1e-2, 1e-3, 1e-4}) {
    const Refined r = Refine(t, plate, Fit(), Adaptive(tolerance));
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(testing::ClosedManifoldProblem(r.model), "") << tolerance;
    const double dense = DenseDeviation(t, r, OutsideMode::kError);
    EXPECT_LE(dense, tolerance) << tolerance;
    EXPECT_LE(r.stats.max_deviation, tolerance);
    EXPECT_GT(Added(r, plate), 0u);
    // Without subdivision the plate's faces cut deep through the cylinder.
    SubdivisionOptions off;
    off.mode = SubdivisionMode::kOff;
    const Refined coarse = Refine(t, plate, Fit(), off);
    EXPECT_GT(DenseDeviation(t, coarse, OutsideMode::kError), dense);
  }
}

TEST(Subdivide, ThinPlateOnTheBumpyBezierStaysWithinTheToleranceAndWatertight) {
  for (int figure : {8, 9, 10}) {
    const Target t = Figure(figure, figure == 10 ? 16 : 10);
    const Mesh plate = testing::ThinPlate(1.0, 1.0, 0.02);
    double size = 0.0;
    for (const Vec2& p : t.sheet.flat) size = std::max(size, p.norm());
    for (double tolerance : {3e-3 * size, 3e-4 * size}) {
      const Refined r = Refine(t, plate, Fit(), Adaptive(tolerance));
      ASSERT_TRUE(r.ok);
      EXPECT_EQ(testing::ClosedManifoldProblem(r.model), "") << figure << " " << tolerance;
      EXPECT_LE(DenseDeviation(t, r, OutsideMode::kError), tolerance) << figure;
      EXPECT_GT(r.stats.edge_points_kept, 0u) << figure;
      EXPECT_GT(r.stats.face_points_kept, 0u) << figure;
    }
  }
}

// A layer of small triangles 1.2 above a short wave (wavelength 0.5,
// amplitude 0.02): the offset surface bends with the rate at which the
// wave's curvature changes, which the screen's estimate once left out (it
// skipped edges and faces that strayed by 0.0074 at tolerance 0.005).
TEST(Subdivide, ALayerHighAboveAShortWaveStaysWithinTheTolerance) {
  WaveSpec wave;
  wave.length = wave.width = 4.0;
  wave.amplitude = 0.02;
  wave.wavelength = 0.5;
  const Target t = Flattened(wave, 64);
  PlacementOptions raised;  // heights as given: the layer at 1.2
  raised.anchor = AnchorMode::kValue;
  const Mesh layer = testing::FlatGrid(1.0, 1.0, 1.5, 1.5, 40, 40, 1.2);
  for (double tolerance : {1e-2, 5e-3}) {
    const Refined r = Refine(t, layer, raised, Adaptive(tolerance));
    ASSERT_TRUE(r.ok);
    EXPECT_LE(r.stats.max_deviation, tolerance) << tolerance;
    EXPECT_LE(DenseDeviation(t, r, OutsideMode::kError), tolerance) << tolerance;
  }
}

TEST(Subdivide, AFlatTargetAddsNoVertex) {
  const Target t = Flattened(Plane(), 8);
  const Mesh plate = testing::ThinPlate(1.5, 1.2, 0.1);
  for (double tolerance : {0.0, 1e-6}) {
    const Refined r = Refine(t, plate, Fit(), Adaptive(tolerance));
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.model.positions.size(), plate.positions.size());
    EXPECT_EQ(r.model.triangles.size(), plate.triangles.size());
    EXPECT_GT(r.stats.edge_points_considered, 0u);  // it looked, and kept none
    EXPECT_EQ(r.stats.edge_points_kept, 0u);
    EXPECT_LT(r.stats.max_deviation, 1e-9);
  }
}

// Adaptive, asked for the deviation that uniform reaches, reaches it with
// markedly fewer vertices where the surface bends in one direction only or
// only in places; on a surface bumpy everywhere (Figure 10) it needs about as
// many.
TEST(Subdivide, AdaptiveMatchesUniformWithMarkedlyFewerVertices) {
  struct Case {
    const char* name;
    Target target;
    double max_ratio;
  };
  std::vector<Case> cases;
  cases.push_back({"cylinder", Flattened(CylinderSpec{1.0, 2.0, 180.0, {}}, 16), 0.5});
  cases.push_back({"cone", Flattened(ConeSpec{1.0, 0.4, 1.0, 240.0, {}}, 16), 0.5});
  cases.push_back({"bump", Flattened(testing::BumpOnAPlane(0.3), 16), 0.6});
  cases.push_back({"figure 10", Figure(10, 16), 1.0});
  const Mesh plate = testing::ThinPlate(1.0, 1.0, 0.02);
  for (const Case& c : cases) {
    SubdivisionOptions uniform;
    uniform.mode = SubdivisionMode::kUniform;
    const Refined u = Refine(c.target, plate, Fit(), uniform);
    ASSERT_TRUE(u.ok) << c.name;
    EXPECT_EQ(testing::ClosedManifoldProblem(u.model), "") << c.name;
    EXPECT_EQ(u.stats.edge_points_kept, u.stats.edge_points_considered);
    EXPECT_EQ(u.stats.face_points_kept, u.stats.face_points_considered);
    const double uniform_dev = DenseDeviation(c.target, u, OutsideMode::kError);
    const Refined a = Refine(c.target, plate, Fit(), Adaptive(uniform_dev));
    ASSERT_TRUE(a.ok) << c.name;
    EXPECT_LE(DenseDeviation(c.target, a, OutsideMode::kError), uniform_dev) << c.name;
    EXPECT_LE(static_cast<double>(a.model.positions.size()),
              c.max_ratio * static_cast<double>(u.model.positions.size()))
        << c.name << ": adaptive " << a.model.positions.size() << ", uniform "
        << u.model.positions.size();
  }
}

// The paper's epsilon alone: grid points only (no tolerance refinement),
// fewer as epsilon rises, none where the surface is flat.
TEST(Subdivide, EpsilonAloneKeepsGridPointsWhereTheSurfaceBends) {
  const Target t = Flattened(testing::BumpOnAPlane(0.3), 16);
  const Mesh plate = testing::ThinPlate(1.0, 1.0, 0.02);
  std::vector<size_t> kept;
  for (double epsilon : {0.5, 2.0, 4.0, 100.0}) {
    SubdivisionOptions s;
    s.epsilon = epsilon;
    const Refined r = Refine(t, plate, Fit(), s);
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(testing::ClosedManifoldProblem(r.model), "") << epsilon;
    EXPECT_EQ(r.stats.refinement_points, 0u);
    EXPECT_EQ(r.stats.tolerance, 0.0);
    EXPECT_LT(r.stats.edge_points_kept, r.stats.edge_points_considered);  // the flat part
    kept.push_back(r.stats.edge_points_kept);
  }
  EXPECT_GT(kept[0], kept[1]);
  EXPECT_GT(kept[1], kept[2]);
  EXPECT_GT(kept[2], 0u);
  EXPECT_EQ(kept[3], 0u);
}

TEST(Subdivide, EveryAttributeIsInterpolatedAndFacesKeepTheirOrientation) {
  const Target t = Figure(10, 16);
  Mesh grid = testing::FlatGrid(-0.5, -0.5, 1.0, 1.0, 2, 2, 0.0);  // 8 large triangles
  grid.uv1 = grid.uv0;
  grid.groups = {{"a", 0, 0, 4}, {"b", 1, 4, 4}};
  const Refined r = Refine(t, grid, Fit(), Adaptive(1e-3));
  ASSERT_TRUE(r.ok);
  const Mesh& m = r.model;
  ASSERT_GT(m.positions.size(), grid.positions.size());
  EXPECT_EQ(CheckMesh(m), "");
  for (size_t k = 0; k < grid.positions.size(); ++k) {
    EXPECT_EQ(m.positions[k], grid.positions[k]);  // the input's vertices first, unchanged
  }
  for (size_t k = 0; k < m.positions.size(); ++k) {
    // The grid's attributes are linear in position: interpolation is exact.
    const Vec3& p = m.positions[k];
    EXPECT_NEAR(m.uv0[k].x(), p.x(), 1e-12);
    EXPECT_NEAR(m.uv1[k].y(), p.y(), 1e-12);
    EXPECT_NEAR(m.colors[k].x(), p.x() + 0.5, 1e-12);
    EXPECT_NEAR(m.normals[k].z(), 1.0, 1e-12);
    EXPECT_NEAR(m.tangents[k].x(), 1.0, 1e-12);
    EXPECT_EQ(m.tangents[k].w(), 1.0);
  }
  for (const auto& tri : m.triangles) {  // all counter-clockwise seen from +z, like the input
    const Vec3 n = (m.positions[tri[1]] - m.positions[tri[0]])
                       .cross(m.positions[tri[2]] - m.positions[tri[0]]);
    EXPECT_GT(n.z(), 0.0);
  }
  ASSERT_EQ(m.groups.size(), 2u);
  EXPECT_EQ(m.groups[0].first_triangle, 0u);
  EXPECT_EQ(m.groups[1].first_triangle, m.groups[0].triangle_count);
  EXPECT_EQ(m.groups[0].triangle_count + m.groups[1].triangle_count, m.triangles.size());
  EXPECT_EQ(m.groups[1].material, 1);
}

TEST(Subdivide, ATextureSeamDoesNotOpenACrack) {
  // The plate with every face's vertices separate (as a mesh with hard edges
  // and per-face UVs comes): edges match by position, not by index.
  const Mesh shared = testing::ThinPlate(1.0, 1.0, 0.02);
  Mesh split;
  for (const auto& tri : shared.triangles) {
    const uint32_t base = static_cast<uint32_t>(split.positions.size());
    for (int k = 0; k < 3; ++k) {
      split.positions.push_back(shared.positions[tri[k]]);
      split.uv0.emplace_back(k, base);
    }
    split.triangles.push_back({base, base + 1, base + 2});
  }
  const Target t = Figure(10, 16);
  const Refined a = Refine(t, shared, Fit(), Adaptive(1e-3));
  const Refined b = Refine(t, split, Fit(), Adaptive(1e-3));
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_EQ(testing::ClosedManifoldProblem(b.model), "");
  EXPECT_EQ(a.model.triangles.size(), b.model.triangles.size());
}

TEST(Subdivide, TheSameOutputWhateverTheThreadCount) {
  const Target t = Figure(10, 16);
  const Mesh sphere = testing::UvSphere(0.3, 48, 32);  // > 2048 triangles: parallel
  auto run = [&](int threads) {
    SubdivisionOptions s = Adaptive(1e-4);
    s.threads = threads;
    return Refine(t, sphere, Fit(), s);
  };
  const Refined one = run(1), three = run(3);
  ASSERT_TRUE(one.ok && three.ok);
  EXPECT_GT(Added(one, sphere), 0u);
  EXPECT_EQ(one.model.positions, three.model.positions);
  EXPECT_EQ(one.model.triangles, three.model.triangles);
}

TEST(Subdivide, FaceExtentsMeasuredAheadChangeNothing) {
  // An animation measures the placed model's face extents once for all its
  // frames. Both a model the screen passes (a fine sphere) and one it
  // refines (a coarse one) give the same output with them as without.
  const Target t = Figure(10, 16);
  const SheetMap map{*t.surface, t.sheet};
  const std::pair<Mesh, double> cases[] = {{testing::UvSphere(1.0, 96, 48), 1e-2},
                                           {testing::UvSphere(0.3, 12, 8), 1e-3}};
  for (const auto& [m, tolerance] : cases) {
    auto pl = ComputePlacement(map, m.positions, Fit());
    ASSERT_TRUE(pl.ok());
    std::vector<Vec3> placed;
    for (const Vec3& p : m.positions) placed.push_back(pl->Apply(p));
    const std::vector<FaceExtent> extents = FaceExtents(m, placed);
    ASSERT_EQ(extents.size(), m.triangles.size());
    const SubdivisionOptions s = Adaptive(tolerance);
    auto without = Subdivide(m, placed, map, OutsideMode::kError, s, InputPositions::kWanted);
    auto with = Subdivide(m, placed, map, OutsideMode::kError, s, InputPositions::kWanted, extents);
    ASSERT_TRUE(without.ok() && with.ok());
    EXPECT_EQ(without->unchanged, with->unchanged);
    EXPECT_EQ(without->unchanged, tolerance == 1e-2) << "the fine sphere passes the screen";
    EXPECT_EQ(without->mesh.positions, with->mesh.positions);
    EXPECT_EQ(without->mesh.triangles, with->mesh.triangles);
    EXPECT_EQ(without->stats.max_estimated_deviation, with->stats.max_estimated_deviation);
    EXPECT_EQ(without->stats.measured_points, with->stats.measured_points);
  }
}

// The thin plate fitted on Figure 10 (16 x 16), placed: the limit tests'
// input.
class SubdivideLimits : public ::testing::Test {
 protected:
  void SetUp() override {
    auto pl = ComputePlacement(map, plate.positions, Fit());
    ASSERT_TRUE(pl.ok()) << pl.status().ToString();
    for (const Vec3& p : plate.positions) placed.push_back(pl->Apply(p));
  }
  const Target t = Figure(10, 16);
  const Mesh plate = testing::ThinPlate(1.0, 1.0, 0.02);
  const SheetMap map{*t.surface, t.sheet};
  std::vector<Vec3> placed;
};

TEST_F(SubdivideLimits, TheOutputSizeLimitIsAClearError) {
  SubdivisionOptions s = Adaptive(1e-7);
  s.max_vertices = 500;
  auto r = Subdivide(plate, placed, map, OutsideMode::kError, s);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_TRUE(r.status().has_limit());
  EXPECT_EQ(r.status().limit(), 500);
  EXPECT_GT(r.status().actual(), 500);
  s.tolerance = -1.0;
  EXPECT_EQ(Subdivide(plate, placed, map, OutsideMode::kError, s).status().field(),
            "subdivision.tolerance");
}

TEST_F(SubdivideLimits, TheTimeBudgetStopsALongRefinement) {
  SubdivisionOptions s = Adaptive(1e-4);
  s.threads = 1;
  // Times as the fastest of three runs: a loaded machine stalls single runs,
  // never all three by the same amount.
  auto fastest = [&](Result<SubdivisionResult>* last) {
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      *last = Subdivide(plate, placed, map, OutsideMode::kError, s);
      best = std::min(
          best,
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
  };
  Result<SubdivisionResult> full = NotComputed();
  const double full_ms = fastest(&full);
  ASSERT_TRUE(full.ok()) << full.status().ToString();
  if (full_ms < 40.0) GTEST_SKIP() << "the refinement takes " << full_ms << " ms here: too quick";

  s.time_budget_ms = full_ms / 8;
  Result<SubdivisionResult> stopped = NotComputed();
  const double stopped_ms = fastest(&stopped);
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.status().code(), ErrorCode::kDeadlineExceeded);
  EXPECT_EQ(stopped.status().field(), "subdivision");
  EXPECT_EQ(stopped.status().limit(), s.time_budget_ms);
  EXPECT_GT(stopped.status().actual(), s.time_budget_ms);
  EXPECT_LT(stopped_ms, full_ms / 2);  // it stopped, rather than finishing and then failing
  s.time_budget_ms = -1;
  EXPECT_EQ(Subdivide(plate, placed, map, OutsideMode::kError, s).status().field(),
            "subdivision.time_budget_ms");
}

TEST(Subdivide, DeformWithSubdivisionPlacesEveryVertexExactly) {
  const Target t = Figure(10, 16);
  const Mesh plate = testing::ThinPlate(1.0, 1.0, 0.02);
  const Refined r = Refine(t, plate, Fit(), Adaptive(1e-3));
  ASSERT_TRUE(r.ok);
  auto d = Deform(SheetMap(*t.surface, t.sheet), Mesh(plate),
                  {.placement = Fit(), .subdivision = Adaptive(1e-3)});
  ASSERT_TRUE(d.ok()) << d.status().ToString();
  ASSERT_EQ(d->mesh.positions.size(), r.deformed.size());
  for (size_t k = 0; k < r.deformed.size(); ++k) {
    EXPECT_LT((d->mesh.positions[k] - r.deformed[k]).norm(), 1e-12) << k;
  }
  EXPECT_EQ(d->mesh.triangles, r.model.triangles);
  EXPECT_EQ(d->stats.subdivision.vertices_after, r.model.positions.size());
  EXPECT_EQ(d->stats.vertices, r.model.positions.size());
}

// A model finer than the grid that needs nothing (the screen passes) deforms
// exactly as without subdivision, with and without normals to carry (the
// deformation reuses the positions the subdivision computed).
TEST(Subdivide, AModelThatNeedsNothingDeformsAsWithoutSubdivision) {
  const Target t = Figure(10, 16);
  const Mesh positions_only = testing::UvSphere(1.0, 96, 48);
  Mesh with_normals = positions_only;
  ComputeVertexNormals(&with_normals);
  for (const Mesh& m : {positions_only, with_normals}) {
    auto off = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = Fit()});
    auto adaptive = Deform(SheetMap(*t.surface, t.sheet), Mesh(m),
                           {.placement = Fit(), .subdivision = Adaptive(1e-2)});
    ASSERT_TRUE(off.ok() && adaptive.ok());
    ASSERT_EQ(adaptive->stats.subdivision.vertices_after, m.positions.size())
        << "the sphere was refined: choose a finer model";
    ASSERT_EQ(adaptive->mesh.positions.size(), off->mesh.positions.size());
    for (size_t k = 0; k < m.positions.size(); ++k) {
      EXPECT_LT((adaptive->mesh.positions[k] - off->mesh.positions[k]).norm(), 1e-12) << k;
    }
    ASSERT_EQ(adaptive->mesh.normals.size(), off->mesh.normals.size());
    for (size_t k = 0; k < m.normals.size(); ++k) {
      EXPECT_LT((adaptive->mesh.normals[k] - off->mesh.normals[k]).norm(), 1e-12) << k;
    }
  }
}

// Random closed meshes (jittered spheres and plates), random placements,
// random targets and tolerances: always valid, closed, consistently oriented.
TEST(Subdivide, RandomMeshesGiveValidConformingOrientableOutput) {
  std::mt19937 rng(20261124);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Target> targets;
  targets.push_back(Figure(8, 10));
  targets.push_back(Figure(10, 16));
  targets.push_back(Flattened(CylinderSpec{1.0, 2.0, 200.0, {}}, 12));
  targets.push_back(Flattened(ConeSpec{1.0, 0.4, 1.0, 240.0, {}}, 12));
  for (int round = 0; round < 24; ++round) {
    Mesh m = round % 2 == 0 ? testing::UvSphere(0.5, 5 + round % 7, 3 + round % 5)
                            : testing::ThinPlate(1.0, 0.2 + unit(rng), 0.05 + 0.2 * unit(rng));
    for (Vec3& p : m.positions) p += 0.05 * Vec3(unit(rng), unit(rng), unit(rng));
    PlacementOptions o = Fit();
    o.rotation_deg = 360.0 * unit(rng);
    o.fit_margin = 0.02 + 0.2 * unit(rng);
    o.up = static_cast<UpAxis>(round % 6);
    o.anchor = static_cast<AnchorMode>(round % 3);
    const Target& t = targets[round % targets.size()];
    SubdivisionOptions s = Adaptive(std::pow(10.0, -2.0 - 2.0 * unit(rng)));
    if (round % 5 == 4) s.mode = SubdivisionMode::kUniform;
    if (round % 7 == 3) s.epsilon = 1.0 + 3.0 * unit(rng);
    const Refined r = Refine(t, m, o, s);
    ASSERT_TRUE(r.ok) << round;
    EXPECT_EQ(CheckMesh(r.model), "") << round;
    EXPECT_EQ(testing::ClosedManifoldProblem(r.model), "") << round;
    for (const Vec3& p : r.deformed) ASSERT_TRUE(p.allFinite()) << round;
    if (s.mode == SubdivisionMode::kAdaptive && s.epsilon == 0.0) {
      EXPECT_LE(DenseDeviation(t, r, o.outside), s.tolerance) << round;
    }
  }
}

}  // namespace
}  // namespace surfdeform
