// A part's body grown from a surface (part/part_body.hpp) and the checks
// every part passes (part/solid_report.hpp): a ring from a whole cylinder
// is a closed, oriented band whose volume is the annulus's, to the
// polygon's own formula; an open patch gets walls; a torus closes both
// ways; a pole, or a thickness past the surface's radius of curvature, is
// refused with the largest thickness possible; and the checks see an open
// mesh, a flipped triangle and two solids crossing.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/surface/surface_spec.hpp"
#include "meshio/mesh_import.hpp"
#include "meshio/print_formats.hpp"
#include "part/part_body.hpp"
#include "part/solid_report.hpp"
#include "service/part_replies.hpp"

namespace surfdeform {
namespace {

constexpr double kPi = std::numbers::pi;

std::unique_ptr<Surface> Made(const SurfaceSpec& spec) {
  auto s = MakeSurface(spec);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  return std::move(*s);
}

// The ring of the issue: 18 mm inside, 6 mm wide, 1.8 mm thick.
constexpr double kInner = 9.0, kWidth = 6.0, kThick = 1.8;

TEST(PartBody, ARingFromAWholeCylinderIsAClosedBandOfTheAnnulussVolume) {
  const auto cylinder = Made(CylinderSpec{kInner, kWidth, 360.0, {}});
  for (BodySide side : {BodySide::kOutside, BodySide::kInside}) {
    BodyOptions o;
    o.thickness = kThick;
    o.side = side;
    o.nu = 256;
    o.nv = 3;
    auto body = ThickenSurface(*cylinder, o);
    ASSERT_TRUE(body.ok()) << body.status().ToString();
    EXPECT_EQ(body->triangles.size(), BodyTriangles(*cylinder, o));
    const SolidReport r = CheckSolid(*body);
    EXPECT_TRUE(r.sound()) << SolidProblem(r, "the ring", "").ToString();
    EXPECT_EQ(r.border_edges, 0u);
    EXPECT_TRUE(r.self_intersection_checked);
    // The cylinder's normal points away from its axis: outside grows the
    // band outward, inside inward.
    const double outer = side == BodySide::kOutside ? kInner + kThick : kInner;
    const double inner = outer - kThick;
    // A polygon of n sides inscribed in radius R has area (n/2) R^2 sin(2 pi / n).
    const double polygon = 0.5 * o.nu * std::sin(2 * kPi / o.nu) * (outer * outer - inner * inner);
    EXPECT_NEAR(r.volume, polygon * kWidth, 1e-9 * r.volume);
    const double annulus = kPi * (outer * outer - inner * inner) * kWidth;
    EXPECT_NEAR(r.volume, annulus, 5e-4 * annulus);
    EXPECT_NEAR(r.hi.z() - r.lo.z(), kWidth, 1e-9);
    EXPECT_NEAR(r.hi.x() - r.lo.x(), 2 * outer, 1e-9);
  }
}

TEST(PartBody, AnOpenPatchGetsSideWalls) {
  const auto half = Made(CylinderSpec{kInner, kWidth, 180.0, {}});
  BodyOptions o;
  o.thickness = kThick;
  o.nu = 129;
  o.nv = 4;
  auto body = ThickenSurface(*half, o);
  ASSERT_TRUE(body.ok()) << body.status().ToString();
  const SolidReport r = CheckSolid(*body);
  EXPECT_TRUE(r.sound()) << SolidProblem(r, "the half ring", "").ToString();
  const double outer = kInner + kThick;
  // Half the polygon of 2 (n - 1) sides.
  const double sides = 2.0 * (o.nu - 1);
  const double polygon =
      0.25 * sides * std::sin(2 * kPi / sides) * (outer * outer - kInner * kInner);
  EXPECT_NEAR(r.volume, polygon * kWidth, 1e-9 * r.volume);
}

TEST(PartBody, AWholeTorusClosesBothWays) {
  const double major = 10.0, minor = 2.0, t = 0.5;
  const auto torus = Made(TorusSpec{major, minor, 0.0, 360.0, -180.0, 180.0, {}});
  ASSERT_TRUE(torus->ClosedInU() && torus->ClosedInV());
  BodyOptions o;
  o.thickness = t;
  o.side = BodySide::kBoth;
  o.nu = 180;
  o.nv = 72;
  auto body = ThickenSurface(*torus, o);
  ASSERT_TRUE(body.ok()) << body.status().ToString();
  const SolidReport r = CheckSolid(*body);
  EXPECT_TRUE(r.sound()) << SolidProblem(r, "the torus", "").ToString();
  // Pappus: the tube's annulus swept round the axis, 2 pi R pi ((r + t/2)^2 - (r - t/2)^2).
  const double shell = 2 * kPi * major * kPi * 2 * minor * t;
  EXPECT_NEAR(r.volume, shell, 2e-3 * shell);
}

TEST(PartBody, APoleOrAThicknessPastTheCurvatureIsRefused) {
  const auto sphere = Made(SphereSpec{5.0, 0.0, 360.0, -90.0, 90.0, {}});
  BodyOptions o;
  o.thickness = 1.0;
  auto pole = ThickenSurface(*sphere, o);
  ASSERT_FALSE(pole.ok());
  EXPECT_EQ(pole.status().code(), ErrorCode::kDegenerate);
  EXPECT_NE(pole.status().message().find("no normal"), std::string::npos);

  const auto cylinder = Made(CylinderSpec{kInner, kWidth, 360.0, {}});
  o.side = BodySide::kInside;
  o.thickness = 10.0;  // more than the radius, inward
  auto folded = ThickenSurface(*cylinder, o);
  ASSERT_FALSE(folded.ok());
  EXPECT_EQ(folded.status().code(), ErrorCode::kDegenerate);
  EXPECT_EQ(folded.status().field(), "body.thickness_mm");
  ASSERT_TRUE(folded.status().has_limit());
  EXPECT_NEAR(folded.status().limit(), 0.95 * kInner, 1e-6);
  // Outward, a cylinder takes any thickness.
  o.side = BodySide::kOutside;
  EXPECT_TRUE(ThickenSurface(*cylinder, o).ok());
  o.thickness = 0;
  EXPECT_EQ(ThickenSurface(*cylinder, o).status().code(), ErrorCode::kInvalidArgument);
}

// A unit cube at `at`, 12 outward triangles.
void AddCube(Mesh* m, const Vec3& at) {
  const uint32_t base = static_cast<uint32_t>(m->positions.size());
  for (int k = 0; k < 8; ++k) m->positions.push_back(at + Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
  const uint32_t faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) m->triangles.push_back({base + f[0], base + f[1], base + f[2]});
}

TEST(SolidReport, SeesAnOpenMeshAFlippedTriangleAndTwoSolidsCrossing) {
  Mesh cube;
  AddCube(&cube, Vec3::Zero());
  SolidReport r = CheckSolid(cube);
  ASSERT_TRUE(r.sound()) << SolidProblem(r, "the cube", "").ToString();
  EXPECT_NEAR(r.volume, 1.0, 1e-12);
  EXPECT_NEAR(r.area, 6.0, 1e-12);

  Mesh open = cube;
  open.triangles.pop_back();
  r = CheckSolid(open);
  EXPECT_EQ(r.border_edges, 3u);
  EXPECT_FALSE(r.self_intersection_checked);
  const Status s = SolidProblem(r, "the body", "body");
  EXPECT_EQ(s.code(), ErrorCode::kDegenerate);
  EXPECT_NE(s.message().find("3 edges border one triangle"), std::string::npos) << s.message();

  Mesh flipped = cube;
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  r = CheckSolid(flipped);
  EXPECT_TRUE(r.closed());
  EXPECT_EQ(r.misoriented_edges, 3u);

  Mesh two = cube;
  AddCube(&two, Vec3(0.5, 0.5, 0.5));
  r = CheckSolid(two);
  EXPECT_TRUE(r.closed() && r.oriented());
  EXPECT_TRUE(r.self_intersects);
  Mesh apart = cube;
  AddCube(&apart, Vec3(2, 0, 0));
  EXPECT_TRUE(CheckSolid(apart).sound());
}

TEST(PrintFormats, TheRingAsStlAnd3mfReadsBackAsWritten) {
  const auto cylinder = Made(CylinderSpec{kInner, kWidth, 360.0, {}});
  BodyOptions o;
  o.thickness = kThick;
  o.nu = 64;
  o.nv = 2;
  auto ring = ThickenSurface(*cylinder, o);
  ASSERT_TRUE(ring.ok());
  const std::string stl = WriteBinaryStl(*ring);
  EXPECT_EQ(stl.size(), 84 + 50 * ring->triangles.size());
  EXPECT_EQ(DetectMeshFormat(stl), MeshFormat::kStl);
  auto read = ImportMesh(stl);
  ASSERT_TRUE(read.ok()) << read.status().ToString();
  ASSERT_EQ(read->mesh.triangles.size(), ring->triangles.size());
  // The importer welds STL's corners back into shared vertices: the same
  // solid, to float32.
  const SolidReport back = CheckSolid(read->mesh);
  EXPECT_TRUE(back.sound()) << SolidProblem(back, "the STL", "").ToString();
  EXPECT_NEAR(back.volume, CheckSolid(*ring).volume, 1e-5 * back.volume);

  auto package = Write3mf(*ring, "ring");
  ASSERT_TRUE(package.ok()) << package.status().ToString();
  EXPECT_EQ(package->substr(0, 2), "PK");  // a zip
  auto c = Read3mfContents(*package);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->unit, "millimeter");
  EXPECT_EQ(c->objects, 1u);
  EXPECT_EQ(c->build_items, 1u);
  EXPECT_EQ(c->vertices, ring->positions.size());
  EXPECT_EQ(c->triangles, ring->triangles.size());
  EXPECT_FALSE(Read3mfContents("PK not a package").ok());
}

TEST(PartReplies, APartStopsWhenItsClockRunsOutOrItsClientIsGone) {
  const auto cylinder = Made(CylinderSpec{kInner, kWidth, 360.0, {}});
  proto::PartRequest r;
  r.part.thickness_mm = kThick;
  const auto stl = proto::OutputFormat::kStl;
  CancelFlag gone;
  gone.Raise();
  auto cancelled = MakePartReply(r, *cylinder, "", stl, false, RequestClock(60000, &gone));
  ASSERT_FALSE(cancelled.ok());
  EXPECT_NE(cancelled.status().message().find("part's body"), std::string::npos)
      << cancelled.status().ToString();
  auto late = MakePartReply(r, *cylinder, "", stl, false, RequestClock(-1));
  EXPECT_EQ(late.status().code(), ErrorCode::kDeadlineExceeded) << late.status().ToString();
  auto made = MakePartReply(r, *cylinder, "", stl, false, RequestClock(60000));
  ASSERT_TRUE(made.ok()) << made.status().ToString();
  EXPECT_EQ(made->content_type, "model/stl");
}

}  // namespace
}  // namespace surfdeform
