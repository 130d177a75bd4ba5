// Surfaces given as meshes: the disk checks and their messages,
// the flattening (a flat mesh, a triangulated cylinder), the map, and
// animations whose keyframes are meshes of one topology.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "engine/animation/animation.hpp"
#include "engine/common/disk_mesh.hpp"
#include "engine/deform/deform.hpp"
#include "engine/flatten/mesh_flatten.hpp"
#include "engine/flatten/sheet_motion.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/surface/mesh_surface.hpp"
#include "engine/surface/surface_spec.hpp"
#include "support/mesh_soup.hpp"
#include "support/sheet_compare.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"

namespace surfdeform {
namespace {

using testing::Grid;
using testing::Soup;

Vec3 Plane(double s, double t) { return Vec3(3.0 * s, 2.0 * t, 0.0); }

Status CheckOf(const Soup& m) { return MakeDiskMesh(m.positions, m.triangles).status(); }

void ExpectRefused(const Soup& m, const std::string& part) {
  const Status s = CheckOf(m);
  EXPECT_EQ(s.code(), ErrorCode::kDegenerate) << s.ToString();
  EXPECT_NE(s.message().find(part), std::string::npos) << s.message();
  EXPECT_EQ(s.field(), "model_id");
}

TEST(DiskMesh, AcceptsAJitteredGridAndFindsItsBoundary) {
  const Soup m = Grid(6, 5, 0.3, 1, Plane);
  auto disk = MakeDiskMesh(m.positions, m.triangles);
  ASSERT_TRUE(disk.ok()) << disk.status().ToString();
  EXPECT_EQ(disk->positions.size(), 30u);
  EXPECT_EQ(disk->boundary.size(), 2u * (5 + 4));
  EXPECT_EQ(disk->welded, 0u);
}

TEST(DiskMesh, WeldsRepeatedVerticesBeforeChecking) {
  // Every triangle with its own three vertices (an STL file): one disk after welding.
  const Soup grid = Grid(4, 4, 0.2, 2, Plane);
  Soup soup;
  for (const auto& t : grid.triangles) {
    std::array<uint32_t, 3> u;
    for (int k = 0; k < 3; ++k) {
      u[k] = static_cast<uint32_t>(soup.positions.size());
      soup.positions.push_back(grid.positions[t[k]] + Vec3(1e-12, 0, 0));
    }
    soup.triangles.push_back(u);
  }
  auto disk = MakeDiskMesh(soup.positions, soup.triangles);
  ASSERT_TRUE(disk.ok()) << disk.status().ToString();
  EXPECT_EQ(disk->positions.size(), 16u);
  EXPECT_EQ(disk->welded, soup.positions.size() - 16);
}

TEST(DiskMesh, RefusesAClosedMesh) {
  Soup tetra;
  tetra.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  ExpectRefused(tetra, "the mesh is closed");
  ExpectRefused(tetra, "cut it open");
}

TEST(DiskMesh, RefusesHolesSayingHowManyAndTheLongest) {
  Soup m = Grid(7, 7, 0.0, 3, Plane);
  // Two holes: drop the two triangles of two interior cells apart.
  const size_t cells[] = {1 + 6 * 1, 4 + 6 * 4};
  testing::SoupTriangles kept;
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    if (f / 2 != cells[0] && f / 2 != cells[1]) kept.push_back(m.triangles[f]);
  }
  m.triangles = kept;
  ExpectRefused(m, "has 2 holes besides its outer boundary (the longest 1.66667 units round");
  ExpectRefused(m, "fill the holes");
}

TEST(DiskMesh, RefusesSeveralComponentsWithTheirSizes) {
  Soup a = Grid(3, 3, 0.0, 4, Plane);
  const Soup b = Grid(2, 2, 0.0, 4, [](double s, double t) -> Vec3 { return Vec3(s + 10, t, 0); });
  const uint32_t offset = static_cast<uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  ExpectRefused(a, "2 separate components (of 8, 2 triangles)");
}

TEST(DiskMesh, RefusesAnEdgeInThreeTriangles) {
  Soup m = Grid(3, 2, 0.0, 5, Plane);
  const uint32_t apex = static_cast<uint32_t>(m.positions.size());
  m.positions.emplace_back(0.5, 0.5, 1.0);
  const auto first = m.triangles[0];
  m.triangles.push_back({first[0], first[2], apex});  // the diagonal (0, 4)
  ExpectRefused(m, "is shared by 3 triangles");
}

TEST(DiskMesh, RefusesANonManifoldVertex) {
  // Two triangles that touch only at vertex 0 (a bow tie).
  Soup m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0), Vec3(-1, -1, 0)};
  m.triangles = {{0, 1, 2}, {0, 3, 4}};
  ExpectRefused(m, "vertex 0 joins triangles that meet nowhere else");
}

TEST(DiskMesh, RefusesZeroAreaTriangles) {
  Soup m = Grid(3, 3, 0.0, 6, Plane);
  m.positions[4] = 0.5 * (m.positions[0] + m.positions[1]);  // triangle (0, 1, 4) is a line
  ExpectRefused(m, "triangle 0 has zero area");
}

TEST(DiskMesh, RefusesAFlippedTriangleNamingIt) {
  Soup m = Grid(4, 4, 0.1, 7, Plane);
  std::swap(m.triangles[5][1], m.triangles[5][2]);
  ExpectRefused(m, "is flipped");
  ExpectRefused(m, "triangle 5");
}

TEST(DiskMesh, RefusesAHandle) {
  // A torus cut open at one cell: one boundary loop, one handle.
  const int nu = 8, nv = 6;
  Soup m;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double a = 2 * std::numbers::pi * i / nu, b = 2 * std::numbers::pi * j / nv;
      m.positions.emplace_back((2 + 0.5 * std::cos(b)) * std::cos(a),
                               (2 + 0.5 * std::cos(b)) * std::sin(a), 0.5 * std::sin(b));
    }
  }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(i % nu + nu * (j % nv)); };
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      if (i == 0 && j == 0) continue;
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  ExpectRefused(m, "1 handle");
}

TEST(DiskMesh, RefusesPastTheVertexLimit) {
  const Soup m = Grid(5, 5, 0.0, 8, Plane);
  DiskMeshOptions o;
  o.max_vertices = 20;
  const Status s = MakeDiskMesh(m.positions, m.triangles, o).status();
  EXPECT_EQ(s.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(s.limit(), 20);
  EXPECT_EQ(s.actual(), 25);
}

FlatMesh Flatten(const Soup& m, FlattenOptions o = {}) {
  auto disk = MakeDiskMesh(m.positions, m.triangles);
  EXPECT_TRUE(disk.ok()) << disk.status().ToString();
  auto flat = FlattenMesh(std::move(*disk), o);
  EXPECT_TRUE(flat.ok()) << flat.status().ToString();
  return flat.ok() ? std::move(*flat) : FlatMesh{};
}

TEST(MeshFlatten, AFlatMeshMapsToItselfByARigidMotion) {
  const Soup m = Grid(12, 9, 0.35, 9, [](double s, double t) -> Vec3 {
    // A plane tilted in space.
    return Vec3(1, 2, 3) + 3.0 * s * Vec3(0.6, 0.8, 0) + 2.0 * t * Vec3(0, 0, 1);
  });
  const FlatMesh f = Flatten(m);
  ASSERT_EQ(f.flat.size(), m.positions.size());
  // Every vertex pair keeps its distance (so the layout is a rigid motion or a
  // reflection), and the triangles keep their orientation (so not a reflection).
  double worst = 0.0;
  for (size_t i = 0; i < f.flat.size(); ++i) {
    for (size_t j = i + 1; j < f.flat.size(); ++j) {
      const double space = (f.mesh.positions[i] - f.mesh.positions[j]).norm();
      worst = std::max(worst, std::abs((f.flat[i] - f.flat[j]).norm() - space));
    }
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(f.quality.folded_cells, 0);
  EXPECT_LT(f.quality.stress, 1e-12);
  EXPECT_NEAR(f.quality.area_ratio_min, 1.0, 1e-12);
  EXPECT_NEAR(f.quality.area_ratio_max, 1.0, 1e-12);
}

TEST(MeshFlatten, AVertexJoiningVeryManyTrianglesIsRefusedBeforeItsPairsAreListed) {
  // A fan: a disk whose centre joins all 3000 rim vertices, so that every
  // pair of vertices is within 2 rings (4.5M pairs).
  Soup fan;
  const int rim = 3000;
  fan.positions.emplace_back(0, 0, 0);
  for (int k = 0; k < rim; ++k) {
    const double a = 2 * std::numbers::pi * k / rim;
    fan.positions.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  for (int k = 0; k + 1 < rim; ++k) {
    fan.triangles.push_back({0, static_cast<uint32_t>(k + 1), static_cast<uint32_t>(k + 2)});
  }
  auto disk = MakeDiskMesh(fan.positions, fan.triangles);
  ASSERT_TRUE(disk.ok()) << disk.status().ToString();
  FlattenOptions o;
  o.max_mesh_pairs = 100'000;
  const Status s = FlattenMesh(std::move(*disk), o).status();
  EXPECT_EQ(s.code(), ErrorCode::kLimitExceeded) << s.ToString();
  EXPECT_EQ(s.field(), "flatten.range");
  EXPECT_EQ(s.limit(), 100'000);
  EXPECT_NE(s.message().find("more than 100000 vertex pairs within 3 rings"), std::string::npos)
      << s.message();
  // An even mesh of the same size is well within it.
  const Soup even = Grid(55, 55, 0.2, 15, Plane);
  auto flat = FlattenMesh(*MakeDiskMesh(even.positions, even.triangles), o);
  EXPECT_TRUE(flat.ok()) << flat.status().ToString();
}

// The largest distance between the flat layout and the exact development
// `develop` of each vertex's parameters, after the best rigid motion in the
// plane (no reflection: a mirrored layout is far off), relative to the
// development's size (its farthest point from its centroid).
template <typename D>
double DevelopmentError(const FlatMesh& f, const Soup& m, const D& develop) {
  const size_t n = f.flat.size();
  std::vector<Vec2> exact(n);
  // The disk keeps the soup's vertex order (no welding, all used).
  for (size_t v = 0; v < n; ++v) exact[v] = develop(m.st[v]);
  Vec2 centroid = Vec2::Zero();
  for (const Vec2& p : exact) centroid += p / static_cast<double>(n);
  double size = 0.0;
  for (const Vec2& p : exact) size = std::max(size, (p - centroid).norm());
  return testing::RigidError(exact, f.flat) / size;
}

TEST(MeshFlatten, ATriangulatedCylinderUnrollsToItsDevelopment) {
  // Half a cylinder of radius 1 and height 2, triangulated irregularly.
  constexpr double kAngle = std::numbers::pi;
  for (int cells : {12, 24}) {
    const Soup m = Grid(cells + 1, cells + 1, 0.3, 10, [](double s, double t) -> Vec3 {
      return Vec3(std::cos(kAngle * s), std::sin(kAngle * s), 2.0 * t);
    });
    const FlatMesh f = Flatten(m);
    const double error = DevelopmentError(
        f, m, [](const Vec2& st) -> Vec2 { return Vec2(kAngle * st.x(), 2.0 * st.y()); });
    // The tessellation's own error: a chord short of its arc by
    // (angle^2 / 24) of it, the angle up to 1.6 cells.
    const double chord = std::pow(1.6 * kAngle / cells, 2) / 24;
    EXPECT_LT(error, chord);
  }
}

std::shared_ptr<const FlatMesh> Shared(const Soup& m) {
  return std::make_shared<const FlatMesh>(Flatten(m));
}

TEST(MeshSurface, EvaluatesToTheMeshAndKnowsWhereItEnds) {
  const Soup m = Grid(9, 7, 0.3, 11, [](double s, double t) -> Vec3 {
    return Vec3(2 * s, t, 0.3 * std::sin(2 * s) * t);
  });
  const auto flat = Shared(m);
  const MeshSurface surface(flat);
  for (size_t v = 0; v < flat->flat.size(); ++v) {
    const Vec2 uv = *surface.InverseUnrolling(flat->flat[v]);
    const SurfacePoint s = surface.Evaluate(uv.x(), uv.y(), 1);
    EXPECT_LT((s.p - m.positions[v]).norm(), 1e-12) << v;
    // The normal there is the vertex's (the interpolated field).
    EXPECT_LT((UnitNormal(s) - flat->normals[v]).norm(), 1e-9) << v;
    EXPECT_EQ(*surface.DomainGap(uv, nullptr), 0.0);
  }
  // Off the mesh, the gap is the distance to the nearest boundary point; on
  // it, the depth is the distance to the boundary (by brute force here).
  const std::vector<int>& loop = flat->mesh.boundary;
  auto to_boundary = [&](const Vec2& p) {
    double d = 1e300;
    for (size_t k = 0; k < loop.size(); ++k) {
      const Vec2 a = flat->flat[loop[k]], b = flat->flat[loop[(k + 1) % loop.size()]];
      const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      d = std::min(d, (a + t * (b - a) - p).norm());
    }
    return d;
  };
  const Vec2 off = surface.index().bounds().min() - Vec2(0.3, 0.2);
  Vec2 nearest;
  const double gap = *surface.DomainGap(*surface.InverseUnrolling(off), &nearest);
  EXPECT_NEAR(gap, to_boundary(off), 1e-12);
  EXPECT_GT(gap, 0.3);
  EXPECT_EQ(*surface.DomainGap(nearest, nullptr), 0.0);
  EXPECT_NEAR(*surface.DomainDepth(*surface.InverseUnrolling(off)), -gap, 1e-12);
  // Far off (the rings would be many; every segment is measured instead).
  const Vec2 far = surface.index().bounds().max() + Vec2(40.0, 25.0);
  EXPECT_NEAR(*surface.DomainGap(*surface.InverseUnrolling(far), nullptr), to_boundary(far), 1e-12);
  const Vec2 centre(0.1, 0.05);
  EXPECT_NEAR(*surface.DomainDepth(*surface.InverseUnrolling(centre)), to_boundary(centre), 1e-12);
}

TEST(MeshSurface, AModelOnAFlatMeshMovesRigidly) {
  const Soup m =
      Grid(10, 8, 0.3, 12, [](double s, double t) -> Vec3 { return Vec3(4 * s, 3 * t, 0.0); });
  const MeshSurface surface(Shared(m));
  auto sheet = FlattenSurface(surface, SamplingOptions{32, 32});
  ASSERT_TRUE(sheet.ok()) << sheet.status().ToString();
  const Mesh model = testing::FlatGrid(-1, -0.5, 2, 1, 6, 3, 0.25);
  auto out = Deform(SheetMap(surface, *sheet), Mesh(model), {.placement = PlacementOptions{}});
  ASSERT_TRUE(out.ok()) << out.status().ToString();
  double worst = 0.0;
  for (size_t i = 0; i < model.positions.size(); ++i) {
    for (size_t j = i + 1; j < model.positions.size(); ++j) {
      const double before = (model.positions[i] - model.positions[j]).norm();
      worst = std::max(worst,
                       std::abs((out->mesh.positions[i] - out->mesh.positions[j]).norm() - before));
    }
    EXPECT_NEAR(out->mesh.positions[i].z(), 0.0, 1e-12);  // heights from the bottom
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(out->stats.outside, 0u);
}

TEST(MeshSurface, APlateAlongATriangulatedCylinderMatchesTheCylinder) {
  // The paper's thin plate along half a cylinder given as control data and
  // as an irregular triangulation of it: equal to within the triangulation's
  // chordal error (the sagitta of its longest edges) and the unrolling's.
  constexpr double kAngle = std::numbers::pi;
  const int cells = 24;
  const Soup m = Grid(cells + 1, cells + 1, 0.3, 13, [](double s, double t) -> Vec3 {
    return Vec3(std::cos(kAngle * s), std::sin(kAngle * s), 2.0 * t);
  });
  const MeshSurface mesh_surface(Shared(m));
  CylinderSpec spec;
  spec.radius = 1.0;
  spec.height = 2.0;
  spec.angle_deg = 180.0;
  auto cylinder = MakeSurface(spec);
  ASSERT_TRUE(cylinder.ok());
  const Mesh plate = testing::ThinPlate(2.0, 1.0, 0.1);
  std::vector<Vec3> along[2];
  for (int k = 0; k < 2; ++k) {
    const Surface& surface = k == 0 ? static_cast<const Surface&>(mesh_surface) : **cylinder;
    auto sheet = FlattenSurface(surface, SamplingOptions{33, 33});
    ASSERT_TRUE(sheet.ok()) << sheet.status().ToString();
    auto out = Deform(SheetMap(surface, *sheet), Mesh(plate), {.placement = PlacementOptions{}});
    ASSERT_TRUE(out.ok()) << out.status().ToString();
    along[k] = out->mesh.positions;
  }
  // The sheets' frames may differ by a half turn, which maps the plate onto
  // itself: compare as point sets.
  const double sagitta = 1.0 - std::cos(1.6 * kAngle / cells / 2);
  double worst = 0.0;
  for (const Vec3& p : along[0]) {
    double nearest = 1e300;
    for (const Vec3& q : along[1]) nearest = std::min(nearest, (p - q).norm());
    worst = std::max(worst, nearest);
  }
  EXPECT_LT(worst, 2 * sagitta);
  EXPECT_GT(worst, 0.0);
}

TEST(MeshSurface, ThePlateAlongATriangulatedFigure10MatchesTheParametricOne) {
  // The paper's Figure 10 patch as a fine irregular triangulation: the plate
  // laid at the same surface point, the same way round, lands where it does
  // on the parametric patch, to within the triangulation's chordal error
  // (the farthest a triangle's centre is from the surface) and the two
  // flattenings' own differences.
  auto figure10 = MakeSurface(testing::LoadBezierFile(testing::DataPath("figure10.json")));
  ASSERT_TRUE(figure10.ok());
  const Surface& patch = **figure10;
  const Soup m = Grid(41, 41, 0.2, 14, [&](double s, double t) { return patch.Position(s, t); });
  double chordal = 0.0;
  for (const auto& t : m.triangles) {
    const Vec2 st = (m.st[t[0]] + m.st[t[1]] + m.st[t[2]]) / 3.0;
    const Vec3 centre = (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3.0;
    chordal = std::max(chordal, (centre - patch.Position(st.x(), st.y())).norm());
  }
  const MeshSurface mesh_surface(Shared(m));
  auto mesh_sheet = FlattenSurface(mesh_surface, SamplingOptions{33, 33});
  auto sheet = FlattenSurface(patch, SamplingOptions{33, 33});
  ASSERT_TRUE(mesh_sheet.ok() && sheet.ok());
  const SheetMap map(patch, *sheet), mesh_map(mesh_surface, *mesh_sheet);
  // The rigid motion from the parametric sheet to the mesh's (the best over
  // the mesh's vertices, each at its parameters on the one and its flat
  // position on the other).
  const FlatMesh& flat = *mesh_surface.flat_mesh();
  std::vector<Vec2> patch_points, mesh_points;
  for (size_t v = 0; v < m.st.size(); ++v) {
    patch_points.push_back(map.SheetPoint(m.st[v]));
    mesh_points.push_back(mesh_sheet->frame_linear * flat.flat[v] + mesh_sheet->frame_offset);
  }
  const testing::RigidMotion to_mesh = testing::BestRigidMotion(mesh_points, patch_points);
  const Eigen::Matrix2d& r = to_mesh.rotation;
  const Mesh plate = testing::ThinPlate(1.5, 1.0, 0.1);
  PlacementOptions on_patch;
  on_patch.center_mode = CenterMode::kSheetUnits;
  on_patch.center = map.SheetPoint(Vec2(0.5, 0.5));
  PlacementOptions on_mesh = on_patch;
  on_mesh.center = to_mesh(on_patch.center);
  on_mesh.rotation_deg = std::atan2(r(1, 0), r(0, 0)) * 180.0 / std::numbers::pi;
  auto along_patch = Deform(SheetMap(patch, *sheet), Mesh(plate), {.placement = on_patch});
  auto along_mesh =
      Deform(SheetMap(mesh_surface, *mesh_sheet), Mesh(plate), {.placement = on_mesh});
  ASSERT_TRUE(along_patch.ok() && along_mesh.ok());
  double worst = 0.0;
  for (size_t v = 0; v < plate.positions.size(); ++v) {
    worst =
        std::max(worst, (along_patch->mesh.positions[v] - along_mesh->mesh.positions[v]).norm());
  }
  EXPECT_LT(worst, chordal);  // measured: 7.4e-4 against 9.7e-3
  EXPECT_GT(chordal, 1e-3);   // a triangulation coarse enough to tell
}

// --- Animations whose keyframes are meshes ----------------------------------

// A keyframe of kind "mesh" with its mesh resolved (as the service does).
Keyframe MeshKey(double time, const Soup& m) {
  auto disk = MakeDiskMesh(m.positions, m.triangles);
  EXPECT_TRUE(disk.ok()) << disk.status().ToString();
  MeshSpec spec;
  spec.model_id = std::to_string(time);
  spec.disk = std::make_shared<const DiskMesh>(std::move(*disk));
  return {time, spec};
}

AnimationSpec MeshAnimation(const std::vector<Keyframe>& keys, int frames) {
  AnimationSpec a;
  a.keyframes = keys;
  a.frames = frames;
  a.interpolation = Interpolation::kLinear;
  return a;
}

const std::vector<Vec2>& FlatOf(const AnimatedSheets& a, int frame) {
  return a.surfaces[frame]->flat_mesh()->flat;
}

// Half a cylinder of radius 1 and the same triangulation bent to radius 1.5
// over 120 degrees: both unroll to the same pi x 2 development.
Soup BentHalfCylinder(double radius) {
  const double angle = std::numbers::pi / radius;
  return Grid(13, 13, 0.3, 21, [&](double s, double t) -> Vec3 {
    return Vec3(radius * std::cos(angle * s), radius * std::sin(angle * s), 2.0 * t);
  });
}

TEST(MeshAnimation, FrameZeroIsTheFirstKeyFlattenedAlone) {
  const Soup first = BentHalfCylinder(1.0), last = BentHalfCylinder(1.5);
  auto sheets =
      FlattenAnimation(MeshAnimation({MeshKey(0, first), MeshKey(1, last)}, 5), {17, 17}, {});
  ASSERT_TRUE(sheets.ok()) << sheets.status().ToString();
  ASSERT_EQ(sheets->surfaces.size(), 5u);
  EXPECT_EQ(FlatOf(*sheets, 0), Flatten(first).flat);  // bit for bit
  EXPECT_FALSE(sheets->frames[0].warm);
  for (int k = 1; k < 5; ++k) EXPECT_TRUE(sheets->frames[k].warm) << k;
  // The sheets: sampled on every frame's flat mesh, as a static one is.
  auto alone = FlattenSurface(MeshSurface(Shared(first)), {17, 17});
  ASSERT_TRUE(alone.ok());
  EXPECT_EQ(sheets->sheets[0].flat, alone->flat);
  EXPECT_EQ(sheets->sheets[0].points, alone->points);
}

TEST(MeshAnimation, AnIsometricBendKeepsTheSheetWhereItWas) {
  // The last key is the first bent without stretching: its sheet is the same
  // development, and it stays where frame 0's is (no jump, no turn), though
  // the frames between (vertices interpolated along chords) are not isometric.
  const Soup first = BentHalfCylinder(1.0), last = BentHalfCylinder(1.5);
  auto sheets =
      FlattenAnimation(MeshAnimation({MeshKey(0, first), MeshKey(1, last)}, 5), {17, 17}, {});
  ASSERT_TRUE(sheets.ok()) << sheets.status().ToString();
  const std::vector<Vec2>&f0 = FlatOf(*sheets, 0), &f4 = FlatOf(*sheets, 4);
  double moved = 0.0;
  for (size_t v = 0; v < f0.size(); ++v) moved = std::max(moved, (f4[v] - f0[v]).norm());
  // The tessellation's error (as for the unrolling above), on a pi x 2 sheet.
  const double chord = std::pow(1.6 * std::numbers::pi / 12, 2) / 24;
  EXPECT_LT(moved, chord * std::numbers::pi);
  EXPECT_GT(moved, 0.0);
}

TEST(MeshAnimation, EveryFrameIsFlattenedAsWellAsItsMeshAlone) {
  // Warm from the frame before, the pairs and factor of frame 0 kept: each
  // frame's stress is its mesh's flattened alone (measured within 5.5e-4,
  // relative). Pairs whose segment leaves the mesh in the frame before's
  // sheet are left free: keeping their distance from a frame before gave
  // up to 1.7x the stress here (40x on 5k vertices).
  const Soup first = BentHalfCylinder(1.0), last = BentHalfCylinder(1.5);
  auto sheets =
      FlattenAnimation(MeshAnimation({MeshKey(0, first), MeshKey(1, last)}, 5), {17, 17}, {});
  ASSERT_TRUE(sheets.ok()) << sheets.status().ToString();
  for (int k = 1; k < 5; ++k) {
    const FlatMesh& warm = *sheets->surfaces[k]->flat_mesh();
    auto alone = FlattenMesh(warm.mesh, {});
    ASSERT_TRUE(alone.ok()) << alone.status().ToString();
    EXPECT_EQ(warm.quality.folded_cells, 0) << k;
    EXPECT_NEAR(warm.quality.stress, alone->quality.stress, 2e-3 * alone->quality.stress) << k;
  }
}

TEST(MeshAnimation, ASheetWhoseLongSideTurnsAcrossTheSquareDoesNotSpin) {
  // A flat 3 x 2 mesh stretched into a 2 x 3 one: every frame is flat, so
  // its sheet is a rigid motion of it, and that motion stays the one of
  // frame 0 (the canonical frame of each frame alone would turn a quarter
  // as the longer side changes at the square).
  auto plane = [](double wide, double high) {
    return Grid(9, 9, 0.2, 23, [=](double s, double t) { return Vec3(wide * s, high * t, 0.0); });
  };
  auto sheets = FlattenAnimation(
      MeshAnimation({MeshKey(0, plane(3.0, 2.0)), MeshKey(1, plane(2.0, 3.0))}, 9), {9, 9}, {});
  ASSERT_TRUE(sheets.ok()) << sheets.status().ToString();
  double first_angle = 0.0;
  for (int k = 0; k < 9; ++k) {
    const FlatMesh& f = *sheets->surfaces[k]->flat_mesh();
    std::vector<Vec2> xy;
    for (const Vec3& p : f.mesh.positions) xy.emplace_back(p.x(), p.y());
    auto motion = BestSheetMotion(xy, f.flat);
    ASSERT_TRUE(motion.ok());
    EXPECT_LT(motion->rms, 1e-9) << k;  // a flat frame flattens to itself
    if (k == 0) first_angle = motion->angle;
    // (A least-squares rigid fit between frames crept round by 4.5e-3 over
    // the 8 frames, the jitter making the stretch look turned.)
    EXPECT_NEAR(std::remainder(motion->angle - first_angle, 2 * std::numbers::pi), 0.0, 1e-9) << k;
  }
}

TEST(MeshAnimation, KeysThatAreNotOneMeshAreRefusedNamingTheKey) {
  const AnimationSpec spec = MeshAnimation(
      {MeshKey(0, BentHalfCylinder(1.0)), MeshKey(1, Grid(12, 13, 0.3, 21, Plane))}, 5);
  const Status s = ValidateAnimation(spec, 100);
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument) << s.ToString();
  EXPECT_EQ(s.field(), "keyframes[1].surface.model_id");
  EXPECT_NE(s.message().find("is a mesh of 156 vertices and 264 triangles"), std::string::npos)
      << s.message();
  EXPECT_NE(s.message().find("must be one mesh moving"), std::string::npos) << s.message();
}

TEST(MeshAnimation, ATriangleCollapsingBetweenTheKeysNamesTheFrame) {
  // The last key is the first turned half a turn about the x axis: halfway,
  // interpolated linearly, every triangle lies on that axis.
  const Soup first = Grid(3, 3, 0.0, 1, Plane);
  Soup last = first;
  for (Vec3& p : last.positions) p = Vec3(p.x(), -p.y(), -p.z());
  const Status s =
      FlattenAnimation(MeshAnimation({MeshKey(0, first), MeshKey(1, last)}, 3), {5, 5}, {})
          .status();
  EXPECT_EQ(s.code(), ErrorCode::kDegenerate) << s.ToString();
  EXPECT_EQ(s.message().rfind("frame 1 (time 0.5", 0), 0u) << s.message();
  EXPECT_NE(s.message().find("triangle 0 collapses to zero area"), std::string::npos)
      << s.message();
}

}  // namespace
}  // namespace surfdeform
