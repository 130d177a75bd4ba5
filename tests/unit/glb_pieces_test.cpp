// A large Draco GLB in pieces: cut past the threshold into a
// power of two of compact pieces, one primitive each, on one quantization
// grid, so that a vertex on a border decodes to the same bits in every
// piece (no crack). The bytes
// do not depend on the threads that encode them.
#include <gtest/gtest.h>

#include <set>
#include <tuple>

#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"
#include "support/test_meshes.hpp"

namespace surfdeform {
namespace {

using Point = std::tuple<double, double, double>;

TEST(GlbPieces, APowerOfTwoPastTheThreshold) {
  EXPECT_EQ(GlbPieces(1'000'000, 0), 1);
  EXPECT_EQ(GlbPieces(100, 100), 1);
  EXPECT_EQ(GlbPieces(101, 100), 2);
  EXPECT_EQ(GlbPieces(200, 100), 2);
  EXPECT_EQ(GlbPieces(201, 100), 4);
  EXPECT_EQ(GlbPieces(401, 100), 8);
  EXPECT_EQ(GlbPieces(100'000, 100), kMaxGlbPieces);
}

// A bumpy grid of 121 x 121 vertices with normals and texture coordinates.
Mesh Bumpy() {
  Mesh m = testing::FlatGrid(-1, -1, 2, 2, 120, 120, 0.0);
  for (Vec3& p : m.positions) p.z() = 0.2 * std::sin(5.0 * p.x()) * std::cos(4.0 * p.y());
  m.normals.clear();
  m.tangents.clear();
  m.colors.clear();
  ComputeVertexNormals(&m);
  return m;
}

struct Decoded {
  std::set<Point> positions;
  size_t vertices = 0, triangles = 0, groups = 0;
};

Decoded Decode(const std::string& glb) {
  auto imported = ImportMesh(glb);
  EXPECT_TRUE(imported.ok()) << imported.status().ToString();
  Decoded d;
  if (!imported.ok()) return d;
  for (const Vec3& p : imported->mesh.positions) d.positions.insert({p.x(), p.y(), p.z()});
  d.vertices = imported->mesh.positions.size();
  d.triangles = imported->mesh.triangles.size();
  d.groups = imported->mesh.groups.size();
  return d;
}

std::string Write(const Mesh& mesh, size_t split_vertices, int threads) {
  ExportOptions o;
  o.glb = GlbEncoding::kDraco;
  o.split_vertices = split_vertices;
  o.threads = threads;
  auto glb = ExportMesh(mesh, MeshFormat::kGlb, o);
  EXPECT_TRUE(glb.ok()) << glb.status().ToString();
  return glb.ok() ? *glb : std::string();
}

TEST(GlbPieces, BordersDecodeToTheSameBitsInEveryPiece) {
  const Mesh mesh = Bumpy();
  const size_t n = mesh.positions.size();
  ASSERT_EQ(GlbPieces(n, 5000), 4);
  const Decoded whole = Decode(Write(mesh, 0, 1));
  const Decoded pieces = Decode(Write(mesh, 5000, 2));
  EXPECT_EQ(whole.groups, 1u);
  EXPECT_EQ(pieces.groups, 4u) << "one primitive per piece";
  EXPECT_EQ(pieces.triangles, mesh.triangles.size());
  EXPECT_GT(pieces.vertices, n) << "border vertices are in two pieces";
  // Each decoded once: a border vertex that decoded differently in two
  // pieces would be two points.
  EXPECT_EQ(whole.positions.size(), n);
  EXPECT_EQ(pieces.positions.size(), n);
}

TEST(GlbPieces, TheBytesDoNotDependOnTheThreads) {
  const Mesh mesh = Bumpy();
  const std::string one = Write(mesh, 5000, 1);
  EXPECT_EQ(Write(mesh, 5000, 2), one);
  EXPECT_EQ(Write(mesh, 5000, 3), one);
  EXPECT_NE(Write(mesh, 0, 2), one);
}

}  // namespace
}  // namespace surfdeform
