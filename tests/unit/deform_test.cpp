// Deformation onto surfaces: analytic cases, invariants, options.
#include "engine/deform/deform.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/surface/surface_spec.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

constexpr double kPi = std::numbers::pi;

using testing::Flattened;
using testing::KeepCoordinates;
using testing::Target;

Mesh DeformOk(const Target& t, const Mesh& m, const PlacementOptions& o) {
  auto r = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? std::move(r).value().mesh : Mesh{};
}

TEST(Deform, PlaneMapsTheModelToItself) {
  BezierSpec plane;  // the square [0, 2]^2 at z = 0, uniform parameterisation
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) plane.control_points.emplace_back(2.0 * i / 3, 2.0 * j / 3, 0.0);
  const Target t = Flattened(plane, 8);
  Mesh m = testing::FlatGrid(-0.5, -0.3, 1.0, 0.8, 6, 5, 0.2);
  const Mesh plate = testing::ThinPlate(0.6, 0.4, 0.1);
  const Mesh out = DeformOk(t, m, KeepCoordinates(m, Vec2(1.0, 1.0)));
  for (size_t k = 0; k < m.positions.size(); ++k) {
    EXPECT_LT((out.positions[k] - (m.positions[k] + Vec3(1, 1, 0))).norm(), 1e-9) << k;
    EXPECT_LT((out.normals[k] - Vec3::UnitZ()).norm(), 1e-9);
    EXPECT_LT((out.tangents[k] - Vec4(1, 0, 0, 1)).norm(), 1e-9);
  }
  const Mesh plate_out = DeformOk(t, plate, KeepCoordinates(plate, Vec2(1.0, 1.0)));
  for (size_t k = 0; k < plate.positions.size(); ++k) {
    EXPECT_LT((plate_out.positions[k] - (plate.positions[k] + Vec3(1, 1, 0))).norm(), 1e-9);
  }
}

TEST(Deform, PlateWrapsTheCylinderAsTheClosedFormSays) {
  const double radius = 2.0, height = 3.0;
  const Target t = Flattened(CylinderSpec{radius, height, 180.0, {}}, 16);
  // The sheet is [0, pi R] x [0, height]; a flat point (a, b) at height h lands at
  // angle a / R, radius R + h, z = b.
  const Mesh m = testing::FlatGrid(-2.0, -1.0, 4.0, 2.0, 20, 10, 0.0);
  const Mesh plate = testing::ThinPlate(4.0, 2.0, 0.2);
  for (const Mesh* model : {&m, &plate}) {
    const Vec2 at(kPi * radius / 2, height / 2);
    const Mesh out = DeformOk(t, *model, KeepCoordinates(*model, at));
    for (size_t k = 0; k < model->positions.size(); ++k) {
      const Vec3& p = model->positions[k];
      const double a = p.x() + at.x(), b = p.y() + at.y(), h = p.z();
      const double theta = a / radius;
      const Vec3 want((radius + h) * std::cos(theta), (radius + h) * std::sin(theta), b);
      EXPECT_LT((out.positions[k] - want).norm(), 1e-6) << k;
      if (!model->normals.empty()) {
        EXPECT_LT((out.normals[k] - Vec3(std::cos(theta), std::sin(theta), 0)).norm(), 1e-9);
        EXPECT_LT((out.tangents[k].head<3>() - Vec3(-std::sin(theta), std::cos(theta), 0)).norm(),
                  1e-9);
      }
    }
  }
}

TEST(Deform, PlateOnTheConeKeepsFlatDistances) {
  // On a developable cone, distances on the surface between deformed points at
  // h = 0 equal their distances in the flat sheet. The surface distance of two
  // points of the cone is their distance once the cone is unrolled from their 3D
  // coordinates.
  const double r0 = 1.0, r1 = 0.5, h = 1.0;
  const Target t = Flattened(ConeSpec{r0, r1, h, 240.0, {}}, 16);
  // The sheet is an annular sector: put the grid around its middle sample.
  const Mesh m = testing::FlatGrid(-0.3, -0.15, 0.6, 0.3, 12, 6, 0.0);
  PlacementOptions o;
  o.anchor = AnchorMode::kValue;
  o.center_mode = CenterMode::kSheetUnits;
  o.center = t.sheet.flat[8 + 16 * 8];
  const Mesh out = DeformOk(t, m, o);
  const double dr = r1 - r0, slant = std::hypot(h, dr);
  auto unroll = [&](const Vec3& p) {
    double theta = std::atan2(p.y(), p.x());
    if (theta < -1e-9) theta += 2 * kPi;
    const double rho = (r0 + dr * p.z() / h) / std::abs(dr) * slant;
    const double phi = theta * std::abs(dr) / slant;
    return Vec2(rho * std::cos(phi), rho * std::sin(phi));
  };
  for (size_t k = 0; k < out.positions.size(); ++k) {
    const Vec3& p = out.positions[k];
    EXPECT_NEAR(std::hypot(p.x(), p.y()), r0 + dr * p.z() / h, 1e-9);  // on the cone
    for (size_t l = 0; l < k; l += 7) {
      const double flat = (m.positions[k] - m.positions[l]).norm();
      EXPECT_NEAR((unroll(p) - unroll(out.positions[l])).norm(), flat, 1e-6);
    }
  }
}

TEST(Deform, BumpySurfaceKeepsGridScaleLengthsWithinTheSheetsDistortion) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  // Edges about one flat cell long, over most of the sheet.
  const Eigen::AlignedBox2d box = [&] {
    Eigen::AlignedBox2d b;
    for (const Vec2& p : t.sheet.flat) b.extend(p);
    return b;
  }();
  const double cell = box.sizes().minCoeff() / 15;
  const int nx = static_cast<int>(0.7 * box.sizes().x() / cell);
  const int ny = static_cast<int>(0.7 * box.sizes().y() / cell);
  const Mesh m = testing::FlatGrid(0, 0, nx * cell, ny * cell, nx, ny, 0.0);
  PlacementOptions o;
  o.anchor = AnchorMode::kValue;
  const Mesh out = DeformOk(t, m, o);
  double worst = 0.0;
  for (const auto& tri : m.triangles) {
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = tri[e], b = tri[(e + 1) % 3];
      const double flat = (m.positions[a] - m.positions[b]).norm();
      const double curved = (out.positions[a] - out.positions[b]).norm();
      worst = std::max(worst, std::abs(curved - flat) / flat);
    }
  }
  // A chord is a little shorter than the arc it spans, hence the small slack.
  EXPECT_LT(worst, 1.5 * t.sheet.quality.max_edge_error + 0.01);
  // Vertices at h = 0 lie on the surface: the nearest surface point (by Newton
  // projection from the vertex's own parameters) is the vertex itself.
  for (size_t k = 0; k < out.positions.size(); k += 13) {
    double best = 1e300;
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i)
        best = std::min(best, (t.sheet.points[i + 16 * j] - out.positions[k]).norm());
    EXPECT_LT(best, 2.0 * cell);  // near the sampled surface
  }
}

TEST(Deform, OutsideTheSheetIsAnErrorThatSaysHowManyAndHowFar) {
  const Target t = Flattened(CylinderSpec{1.0, 1.0, 90.0, {}}, 8);     // 1.571 x 1 sheet
  const Mesh m = testing::FlatGrid(-1.0, -0.25, 2.0, 0.5, 4, 1, 0.0);  // 2.0 wide
  PlacementOptions o;
  auto r = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kOutsideSheet);
  EXPECT_NE(r.status().message().find("4 of 10 vertices"), std::string::npos)
      << r.status().message();
  EXPECT_NE(r.status().message().find("0.214602"), std::string::npos) << r.status().message();
}

// Numbers past what the placement can mean are refused naming their field:
// a centre past +-1e15 (the arithmetic would overflow), and a numeric
// anchor further outside the model's heights than ten times its size (the
// model would float off the surface, its offset refined without end).
TEST(Deform, PlacementNumbersPastTheirMeaningNameTheirField) {
  const Target t = Flattened(CylinderSpec{1.0, 1.0, 90.0, {}}, 8);
  const Mesh m = testing::FlatGrid(-0.2, -0.2, 0.4, 0.4, 2, 2, 0.0);  // 0.4 across, flat
  auto error = [&](const PlacementOptions& o) {
    auto r = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o});
    return r.ok() ? Status::Ok() : r.status();
  };
  PlacementOptions o;
  o.center_mode = CenterMode::kSheetUnits;
  o.center = Vec2(1e300, 0.0);
  EXPECT_EQ(error(o).field(), "placement.center");
  EXPECT_EQ(error(o).code(), ErrorCode::kInvalidArgument);
  o = PlacementOptions{};
  o.anchor = AnchorMode::kValue;
  o.anchor_value = 1e30;
  EXPECT_EQ(error(o).field(), "placement.anchor");
  o.anchor_value = 4.1;  // 4.1 outside the heights, over 10 x 0.4
  EXPECT_EQ(error(o).field(), "placement.anchor");
  EXPECT_NE(error(o).message().find("float off the surface"), std::string::npos);
  o.anchor_value = -3.9;  // within: the model floats 3.9 above the surface
  EXPECT_TRUE(error(o).ok()) << error(o).ToString();
}

TEST(Deform, ClampPutsOutsideVerticesOnTheBorder) {
  const Target t = Flattened(CylinderSpec{1.0, 1.0, 90.0, {}}, 8);
  const Mesh m = testing::FlatGrid(-1.0, -0.25, 2.0, 0.5, 4, 1, 0.0);
  PlacementOptions o;
  o.outside = OutsideMode::kClamp;
  auto r = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->stats.outside, 4u);
  for (size_t k : {0u, 4u, 5u, 9u}) {  // the columns at x = -1 and x = +1
    const Vec3& p = r->mesh.positions[k];
    const double angle = std::atan2(p.y(), p.x());
    EXPECT_TRUE(std::abs(angle) < 1e-9 || std::abs(angle - kPi / 2) < 1e-9) << angle;
  }
}

TEST(Deform, ExtrapolateContinuesTheSurfaceSmoothly) {
  const Target t = Flattened(CylinderSpec{1.0, 1.0, 90.0, {}}, 8);
  const Mesh m = testing::FlatGrid(-1.0, 0.0, 2.0, 0.0, 40, 1, 0.0);  // crosses both sides
  PlacementOptions o;
  o.outside = OutsideMode::kExtrapolate;
  auto r = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  // The cylinder continues past its angle range: every point stays on the
  // unit circle and consecutive points keep their flat spacing (as arc length).
  for (int k = 0; k + 1 <= 40; ++k) {
    const Vec3& p = r->mesh.positions[k];
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 1.0, 1e-9);
    const Vec3& q = r->mesh.positions[k + 1];
    const double chord = (p - q).norm();
    EXPECT_NEAR(chord, 2 * std::sin(0.05 / 2), 1e-9) << k;
  }
}

TEST(Deform, FitKeepsTheFootprintInsideWithTheMargin) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure9.json")), 10);
  const Mesh m = testing::FlatGrid(-3, -1, 6, 2, 30, 10, 0.0);
  PlacementOptions o;
  o.fit = true;
  o.rotation_deg = 30;
  auto r = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->stats.outside, 0u);
  EXPECT_GT(r->stats.scale, 0.5);
  // A 1% larger scale no longer fits.
  o.fit = false;
  o.scale = r->stats.scale * 1.05;
  EXPECT_FALSE(Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o}).ok());
}

TEST(Deform, FitDependsOnlyOnTheFootprintsOutline) {
  // 48 points on an ellipse (all on the convex hull) and, with them, 20,000
  // inside it, many close to the outline, and midpoints of the outline's edges:
  // the fitted scale must be the one of the outline alone, so the hull's
  // shortcuts (dropping points that cannot be on it) lose no hull vertex.
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure9.json")), 10);
  const SheetMap map(*t.surface, t.sheet);
  std::vector<Vec3> outline, all;
  for (int k = 0; k < 48; ++k) {
    const double a = 2 * kPi * (k + 0.37 * std::sin(7.0 * k)) / 48;
    outline.push_back(Vec3(3 * std::cos(a), 1.2 * std::sin(a), 0.1 * k));
  }
  all = outline;
  for (int k = 0; k < 48; ++k) all.push_back(0.5 * (outline[k] + outline[(k + 1) % 48]));
  for (int k = 0; k < 20000; ++k) {
    const double a = 0.7 * k, r = 1.0 - std::pow(std::fmod(0.618034 * k, 1.0), 4);
    all.push_back(Vec3(0.99 * r * 3 * std::cos(a), 0.99 * r * 1.2 * std::sin(a), 0.0));
  }
  PlacementOptions o;
  o.fit = true;
  o.rotation_deg = 20;
  auto alone = ComputePlacement(map, outline, o);
  auto with_cloud = ComputePlacement(map, all, o);
  ASSERT_TRUE(alone.ok() && with_cloud.ok());
  EXPECT_GT(alone->scale, 0.1);
  EXPECT_EQ(with_cloud->scale, alone->scale);
}

TEST(Deform, UpAxisChoosesTheNormalDirection) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure8.json")), 10);
  const Mesh z_up = testing::ThinPlate(2.0, 1.0, 0.3);
  for (UpAxis up : {UpAxis::kPosX, UpAxis::kNegX, UpAxis::kPosY, UpAxis::kNegY, UpAxis::kNegZ}) {
    // The same model turned so that `up` points where +Z pointed.
    Mesh turned = z_up;
    for (Vec3& p : turned.positions) {
      const Vec3 q = p;
      switch (up) {
        case UpAxis::kPosX:
          p = Vec3(q.z(), q.x(), q.y());
          break;
        case UpAxis::kNegX:
          p = Vec3(-q.z(), q.x(), -q.y());
          break;
        case UpAxis::kPosY:
          p = Vec3(q.y(), q.z(), q.x());
          break;
        case UpAxis::kNegY:
          p = Vec3(-q.y(), -q.z(), q.x());
          break;
        default:
          p = Vec3(q.x(), -q.y(), -q.z());
      }
    }
    PlacementOptions oz, ou;
    ou.up = up;
    const Mesh a = DeformOk(t, z_up, oz);
    const Mesh b = DeformOk(t, turned, ou);
    for (size_t k = 0; k < a.positions.size(); ++k) {
      EXPECT_LT((a.positions[k] - b.positions[k]).norm(), 1e-9) << static_cast<int>(up);
    }
  }
}

TEST(Deform, KeepsEveryAttributeAndTheVertexOrder) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  Mesh m = testing::FlatGrid(-2, -2, 4, 4, 10, 10, 0.1);
  m.uv1 = m.uv0;
  m.groups = {{"a", 0, 0, 100}, {"b", 1, 100, 100}};
  const Mesh out = DeformOk(t, m, {});
  EXPECT_EQ(out.positions.size(), m.positions.size());
  EXPECT_EQ(out.triangles, m.triangles);
  EXPECT_EQ(out.uv0, m.uv0);
  EXPECT_EQ(out.uv1, m.uv1);
  EXPECT_EQ(out.colors, m.colors);
  ASSERT_EQ(out.groups.size(), 2u);
  EXPECT_EQ(out.groups[1].name, "b");
  for (size_t k = 0; k < out.positions.size(); ++k) {
    EXPECT_TRUE(out.positions[k].allFinite());
    EXPECT_NEAR(out.normals[k].norm(), 1.0, 1e-12);
    EXPECT_NEAR(out.tangents[k].head<3>().norm(), 1.0, 1e-12);
    EXPECT_NEAR(out.normals[k].dot(out.tangents[k].head<3>()), 0.0, 1e-9);
  }
}

TEST(Deform, NormalsFollowTheNewShape) {
  // A fine grid: the face normals of the deformed mesh and the transformed
  // vertex normals agree (to the discretisation error).
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure9.json")), 10);
  const Mesh m = testing::FlatGrid(-2, -2, 4, 4, 80, 80, 0.3);
  const Mesh out = DeformOk(t, m, {});
  double worst = 0.0;
  for (const auto& tri : out.triangles) {
    const Vec3 face = (out.positions[tri[1]] - out.positions[tri[0]])
                          .cross(out.positions[tri[2]] - out.positions[tri[0]])
                          .normalized();
    worst = std::max(worst, 1.0 - face.dot(out.normals[tri[0]]));
  }
  EXPECT_LT(worst, 1e-3);
}

TEST(Deform, ResultDoesNotDependOnThreadCount) {
  const Target t = Flattened(testing::LoadBezierFile(testing::DataPath("figure10.json")), 16);
  const Mesh m = testing::FlatGrid(-3, -3, 6, 6, 100, 100, 0.2);
  PlacementOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const Mesh a = DeformOk(t, m, one);
  const Mesh b = DeformOk(t, m, two);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
}

// A vertex whose deformation is not finite is an error that names it, with
// and without a frame to carry (the batched map without one moves the
// positions along the normal in Surface::OffsetMany). Laid on the plane's
// sheet, the surface mapped to is a line (S_v = 0): no normal anywhere.
TEST(Deform, NoNormalIsAnErrorThatNamesTheFirstVertex) {
  BezierSpec plane, line;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      plane.control_points.emplace_back(2.0 * i / 3, 2.0 * j / 3, 0.0);
      line.control_points.emplace_back(2.0 * i / 3, 0.0, 0.0);
    }
  }
  const Target t = Flattened(plane, 8);
  const std::unique_ptr<Surface> no_normal = testing::MakeValid(line);
  Mesh framed = testing::FlatGrid(-0.5, -0.3, 1.0, 0.8, 6, 5, 0.2);
  Mesh bare = framed;
  bare.normals.clear();
  bare.tangents.clear();
  ASSERT_FALSE(framed.normals.empty());
  for (const Mesh* m : {&framed, &bare}) {
    auto ok = Deform(SheetMap(*t.surface, t.sheet), *m,
                     {.placement = KeepCoordinates(*m, Vec2(1.0, 1.0))});
    ASSERT_TRUE(ok.ok()) << ok.status().ToString();
    auto r = Deform(SheetMap(*no_normal, t.sheet), *m,
                    {.placement = KeepCoordinates(*m, Vec2(1.0, 1.0))});
    ASSERT_FALSE(r.ok()) << (m == &bare ? "without" : "with") << " a frame";
    EXPECT_NE(r.status().message().find("deformation of vertex 0 is not finite"), std::string::npos)
        << r.status().ToString();
  }
}

TEST(Deform, RejectsBadPlacement) {
  const Target t = Flattened(WaveSpec{}, 8);
  const Mesh m = testing::ThinPlate(0.5, 0.5, 0.1);
  PlacementOptions o;
  o.scale = -1;
  EXPECT_EQ(Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o}).status().field(),
            "placement.scale");
  o = {};
  o.rotation_deg = std::nan("");
  EXPECT_EQ(Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o}).status().field(),
            "placement.rotation_deg");
  Mesh broken = m;
  broken.triangles.push_back({0, 1, 99});
  EXPECT_EQ(Deform(SheetMap(*t.surface, t.sheet), broken, {.placement = {}}).status().field(),
            "mesh");
  broken = m;
  broken.positions[3].x() = std::nan("");
  EXPECT_EQ(Deform(SheetMap(*t.surface, t.sheet), broken, {.placement = {}}).status().field(),
            "mesh.positions[3]");
}

}  // namespace
}  // namespace surfdeform
