// Subdivision stage: the refined mesh.
#include "engine/subdivision/assembly.hpp"

#include <gtest/gtest.h>

#include "stage_test_util.hpp"

namespace surfdeform::subdivision {
namespace {

Result<SubdivisionResult> AssembleOn(const testing::StageInputs& in,
                                     const testing::StagesThroughFaces& s) {
  return Assemble(*in.ctx, s.graph, s.marking, s.edges, s.faces, SubdivisionStats{});
}

size_t KeptOnEdges(const testing::StagesThroughFaces& s) {
  size_t n = 0;
  for (const RefinedEdge& e : s.edges) n += e.kept_t.size();
  return n;
}
size_t Inside(const testing::StagesThroughFaces& s) {
  size_t n = 0;
  for (const FaceOutput& f : s.faces)
    for (const LocalPoint& p : f.points) n += p.kind == LocalPoint::Kind::kInside;
  return n;
}

TEST(Assembly, InputVerticesComeFirstAndEachEdgePointOnce) {
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0), testing::ThinPlate(2.4, 1.6, 0.1),
                                     testing::Tolerance(1e-3));
  const auto s = testing::RunThroughFaces(*in);
  auto r = AssembleOn(*in, *s);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  for (size_t k = 0; k < in->mesh.positions.size(); ++k) {
    EXPECT_EQ(r->mesh.positions[k], in->mesh.positions[k]);
    EXPECT_EQ(r->placed[k], in->placed[k]);
  }
  EXPECT_EQ(r->mesh.positions.size(), in->mesh.positions.size() + KeptOnEdges(*s) + Inside(*s));
  EXPECT_EQ(r->placed.size(), r->mesh.positions.size());
  EXPECT_EQ(testing::ClosedManifoldProblem(r->mesh), "");
  EXPECT_EQ(r->stats.vertices_after, r->mesh.positions.size());
  EXPECT_EQ(r->stats.triangles_after, r->mesh.triangles.size());
  EXPECT_GT(r->stats.refinement_points, 0u);
}

TEST(Assembly, ASeamGetsItsOwnVerticesAtTheSamePositions) {
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0),
                                     testing::Unwelded(testing::ThinPlate(2.4, 1.6, 0.1)),
                                     testing::Tolerance(1e-3));
  const auto s = testing::RunThroughFaces(*in);
  auto r = AssembleOn(*in, *s);
  ASSERT_TRUE(r.ok());
  // Every edge is a seam: its points twice, once for each pair of vertices.
  EXPECT_EQ(r->mesh.positions.size(), in->mesh.positions.size() + 2 * KeptOnEdges(*s) + Inside(*s));
  EXPECT_EQ(testing::ClosedManifoldProblem(r->mesh), "");  // by position: no crack
}

TEST(Assembly, AttributesAreInterpolatedAndGroupsCoverTheirFaces) {
  Mesh grid = testing::FlatGrid(-1, -1, 2, 2, 2, 2, 0.0);  // 8 triangles, normals, uv, colours
  grid.groups = {{"a", -1, 0, 3}, {"b", -1, 3, 5}};
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0), grid, testing::Tolerance(1e-3));
  const auto s = testing::RunThroughFaces(*in);
  auto r = AssembleOn(*in, *s);
  ASSERT_TRUE(r.ok());
  const Mesh& out = r->mesh;
  ASSERT_GT(out.positions.size(), grid.positions.size());
  ASSERT_EQ(out.groups.size(), 2u);
  EXPECT_EQ(out.groups[0].first_triangle, 0u);
  EXPECT_EQ(out.groups[1].first_triangle, out.groups[0].triangle_count);
  EXPECT_EQ(out.groups[0].triangle_count + out.groups[1].triangle_count, out.triangles.size());
  for (size_t k = grid.positions.size(); k < out.positions.size(); ++k) {
    // On the flat grid uv0 = (x, y) and the colour's red and green are affine
    // in x and y: interpolation keeps those relations.
    EXPECT_NEAR(out.uv0[k].x(), out.positions[k].x(), 1e-12);
    EXPECT_NEAR(out.uv0[k].y(), out.positions[k].y(), 1e-12);
    EXPECT_NEAR(out.colors[k].x(), (out.positions[k].x() + 1) / 2, 1e-12);
    EXPECT_NEAR(out.normals[k].z(), 1.0, 1e-12);
    EXPECT_NEAR(out.tangents[k].head<3>().norm(), 1.0, 1e-12);
  }
}

TEST(Assembly, PastTheTriangleLimitIsAnErrorWithTheLimitAndTheSize) {
  SubdivisionOptions o = testing::Tolerance(1e-3);
  o.max_triangles = 50;
  auto in = testing::MakeStageInputs(testing::Cylinder(1.0), testing::ThinPlate(2.4, 1.6, 0.1), o);
  const auto s = testing::RunThroughFaces(*in);
  auto r = AssembleOn(*in, *s);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(r.status().limit(), 50.0);
  EXPECT_GT(r.status().actual(), 50.0);
}

}  // namespace
}  // namespace surfdeform::subdivision
