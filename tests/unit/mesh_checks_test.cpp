// The checks every request's mesh passes three times (import, deformation,
// export): they find the first offending index and value, wherever it is.
#include <gtest/gtest.h>

#include <limits>

#include "engine/common/mesh.hpp"
#include "engine/deform/deform.hpp"
#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(FirstNonFinite, FindsTheFirstVectorWithANonFiniteComponent) {
  std::vector<Vec3> v(1000, Vec3(1.0, -2.0, 3.0));
  // The extremes of the finite doubles are finite.
  v[10] = Vec3(std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(), -0.0);
  v[11] = Vec3(std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(), 0.0);
  EXPECT_EQ(FirstNonFinite(v), -1);
  EXPECT_EQ(FirstNonFinite(std::vector<Vec3>{}), -1);
  v[700].z() = kNaN;
  v[901].x() = kInf;
  EXPECT_EQ(FirstNonFinite(v), 700);
  v[700].z() = 0.0;
  EXPECT_EQ(FirstNonFinite(v), 901);
  std::vector<Vec2> uv(5, Vec2(0.5, 0.5));
  uv[4].y() = -kInf;  // the last component of the last vector
  EXPECT_EQ(FirstNonFinite(uv), 4);
  std::vector<Vec4> colors(3, Vec4::Ones());
  colors[0].w() = kNaN;
  EXPECT_EQ(FirstNonFinite(colors), 0);
}

TEST(FirstBeyondFloat, FindsTheFirstVectorAFloatCannotHold) {
  std::vector<Vec3> v(1000, Vec3(1.0, -2.0, 3.0));
  v[10] = Vec3(1e38, -1e38, std::numeric_limits<double>::denorm_min());  // a float holds these
  EXPECT_EQ(FirstBeyondFloat(v), -1);
  v[500].y() = -2e38;  // 2^127 is 1.7e38
  v[800].x() = 1e300;
  EXPECT_EQ(FirstBeyondFloat(v), 500);
  EXPECT_EQ(FirstNonFinite(v), -1);
  v[500].y() = 0.0;
  EXPECT_EQ(FirstBeyondFloat(v), 800);
  v[800].x() = kNaN;
  EXPECT_EQ(FirstBeyondFloat(v), 800);
  // Every output format writes float32: a double past its range is refused.
  Mesh m = testing::ThinPlate(1.0, 1.0, 0.1);
  m.positions[3].z() = 1e300;
  for (MeshFormat f : {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kDraco, MeshFormat::kGlb}) {
    auto r = ExportMesh(m, f);
    EXPECT_EQ(r.status().code(), ErrorCode::kInvalidArgument) << MeshFormatName(f);
    EXPECT_NE(r.status().message().find("float32"), std::string::npos) << r.status().message();
  }
}

TEST(CheckMesh, NamesTheFirstTriangleWithAnIndexOutOfRange) {
  Mesh m = testing::ThinPlate(1.0, 1.0, 0.1);  // 8 vertices
  ASSERT_EQ(m.positions.size(), 8u);
  EXPECT_EQ(CheckMesh(m), "");
  m.triangles[5][1] = 8;
  m.triangles[9][2] = 4000000000u;
  EXPECT_EQ(CheckMesh(m), "triangle 5 uses vertex 8 of 8");
  m.triangles[5][1] = 7;  // the largest index in range
  EXPECT_EQ(CheckMesh(m), "triangle 9 uses vertex 4000000000 of 8");
  m.triangles[9][2] = 0;
  EXPECT_EQ(CheckMesh(m), "");
  m.triangles[3][0] = 8;  // alone: the largest index is the count
  EXPECT_EQ(CheckMesh(m), "triangle 3 uses vertex 8 of 8");
  m.triangles[3][0] = 0;
  m.positions.clear();  // no vertex: every index is out of range
  m.normals.clear();
  m.tangents.clear();
  m.uv0.clear();
  EXPECT_EQ(CheckMesh(m), "triangle 0 uses vertex " + std::to_string(m.triangles[0][0]) + " of 0");
}

TEST(MeshChecks, ADeformationNamesTheFirstNonFinitePosition) {
  BezierSpec plane;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) plane.control_points.emplace_back(2.0 * i / 3, 2.0 * j / 3, 0.0);
  const testing::Target t = testing::Flattened(plane, 8);
  Mesh m = testing::FlatGrid(-0.5, -0.3, 1.0, 0.8, 6, 5, 0.2);
  const PlacementOptions o = testing::KeepCoordinates(m, Vec2(1.0, 1.0));  // of the finite mesh
  ASSERT_TRUE(Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o}).ok());
  m.positions[17].y() = kNaN;
  m.positions[23].x() = kInf;
  auto r = Deform(SheetMap(*t.surface, t.sheet), m, {.placement = o});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(r.status().field(), "mesh.positions[17]");
}

TEST(MeshChecks, ImportNamesTheFirstNonFinitePosition) {
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n";
  ASSERT_TRUE(ImportMesh(obj).ok());
  std::string bad = obj;
  bad.replace(bad.find("v 1 1 0"), 7, "v 1 1 inf");
  bad.replace(bad.find("v 0 1 0"), 7, "v 0 nan 0");
  auto r = ImportMesh(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(r.status().message().find("vertex 2 has a non-finite position"), std::string::npos)
      << r.status().message();
}

TEST(MeshChecks, ExportRefusesANonFiniteAttribute) {
  Mesh m = testing::ThinPlate(1.0, 1.0, 0.1);
  ComputeVertexNormals(&m);
  ASSERT_TRUE(ExportMesh(m, MeshFormat::kPly).ok());
  m.normals[7].z() = kNaN;
  for (MeshFormat f : {MeshFormat::kPly, MeshFormat::kDraco, MeshFormat::kGlb}) {
    auto out = ExportMesh(m, f);
    ASSERT_FALSE(out.ok()) << MeshFormatName(f);
    EXPECT_EQ(out.status().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(out.status().message().find("non-finite"), std::string::npos);
  }
}

}  // namespace
}  // namespace surfdeform
