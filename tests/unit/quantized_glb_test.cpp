// GLB with meshopt compression and its quantized twin: decoded
// with meshoptimizer's own decoders, the compressed file holds exactly the
// twin's data, and the twin holds the mesh within its quantization.
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>

#include "meshio/mesh_export.hpp"
#include "support/test_meshes.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;

struct Glb {
  json doc;
  std::string bin;
};

Glb Split(const std::string& glb) {
  uint32_t json_length = 0, bin_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  Glb out;
  out.doc = json::parse(glb.substr(20, json_length));
  const size_t bin_at = 20 + json_length;
  std::memcpy(&bin_length, glb.data() + bin_at, 4);
  out.bin = glb.substr(bin_at + 8, bin_length);
  return out;
}

// A buffer view's bytes as a reader gets them: decompressed (and
// unfiltered) when it carries EXT_meshopt_compression.
std::string ViewBytes(const Glb& g, int index) {
  const json& view = g.doc.at("bufferViews").at(index);
  const auto ext = view.find("extensions");
  if (ext == view.end() || !ext->contains("EXT_meshopt_compression")) {
    return g.bin.substr(view.value("byteOffset", size_t{0}), view.at("byteLength").get<size_t>());
  }
  const json& m = ext->at("EXT_meshopt_compression");
  const size_t count = m.at("count"), stride = m.at("byteStride");
  const auto* source =
      reinterpret_cast<const unsigned char*>(g.bin.data()) + m.value("byteOffset", size_t{0});
  const size_t length = m.at("byteLength");
  std::string out(count * stride, '\0');
  int rc = -1;
  if (m.at("mode") == "TRIANGLES") {
    rc = meshopt_decodeIndexBuffer(out.data(), count, stride, source, length);
  } else {
    rc = meshopt_decodeVertexBuffer(out.data(), count, stride, source, length);
    if (m.value("filter", "NONE") == "OCTAHEDRAL")
      meshopt_decodeFilterOct(out.data(), count, stride);
  }
  EXPECT_EQ(rc, 0) << "view " << index;
  return out;
}

// Every attribute at once: normals, tangents, two UV sets (one outside
// [0, 1]), colours, the distortion, two groups with materials.
Mesh Everything() {
  Mesh m = testing::FlatGrid(-1, -1, 2, 2, 20, 20, 0.0);
  for (Vec3& p : m.positions) p.z() = 0.3 * std::sin(2.0 * p.x()) * std::cos(3.0 * p.y());
  m.normals.clear();
  ComputeVertexNormals(&m);
  m.uv1 = m.uv0;
  for (Vec2& t : m.uv1) t *= 3.0;  // outside [0, 1]: floats
  m.distortion.assign(m.positions.size(), Vec2(0.01, -0.02));
  const auto half = static_cast<uint32_t>(m.triangles.size() / 2);
  m.groups = {{"a", 0, 0, half}, {"b", 1, half, static_cast<uint32_t>(m.triangles.size()) - half}};
  return m;
}

Glb Write(const Mesh& mesh, GlbEncoding encoding) {
  ExportOptions o;
  o.glb = encoding;
  o.materials = {"red", "blue"};
  auto glb = ExportMesh(mesh, MeshFormat::kGlb, o);
  EXPECT_TRUE(glb.ok()) << glb.status().ToString();
  return glb.ok() ? Split(*glb) : Glb{};
}

TEST(QuantizedGlb, MeshoptDecodesToItsUncompressedTwinByteForByte) {
  const Mesh mesh = Everything();
  const Glb packed = Write(mesh, GlbEncoding::kMeshopt);
  const Glb twin = Write(mesh, GlbEncoding::kQuantized);
  const size_t views = twin.doc.at("bufferViews").size();
  ASSERT_EQ(packed.doc.at("bufferViews").size(), views);
  int compressed = 0, filtered = 0;
  for (size_t v = 0; v < views; ++v) {
    const json& view = packed.doc["bufferViews"][v];
    if (view.contains("extensions")) {
      ++compressed;
      filtered += view["extensions"]["EXT_meshopt_compression"].contains("filter");
    }
    EXPECT_EQ(ViewBytes(packed, static_cast<int>(v)), ViewBytes(twin, static_cast<int>(v)))
        << "buffer view " << v;
  }
  // Seven attributes and two index buffers, the normals and tangents filtered.
  EXPECT_EQ(compressed, 9);
  EXPECT_EQ(filtered, 2);
  EXPECT_EQ(packed.doc["extensionsRequired"],
            json({"KHR_mesh_quantization", "EXT_meshopt_compression"}));
  EXPECT_EQ(twin.doc["extensionsRequired"], json({"KHR_mesh_quantization"}));
  EXPECT_LT(packed.bin.size(), twin.bin.size() / 2);
}

TEST(QuantizedGlb, HoldsTheMeshWithinItsQuantization) {
  const Mesh mesh = Everything();
  const Glb g = Write(mesh, GlbEncoding::kQuantized);
  const json& prim0 = g.doc["meshes"][0]["primitives"][0];
  const json& node = g.doc["nodes"][0];
  const double scale = node["scale"][0];
  const Vec3 origin(node["translation"][0], node["translation"][1], node["translation"][2]);
  auto accessor_view = [&](const char* name) {
    return ViewBytes(g, g.doc["accessors"][prim0["attributes"][name].get<int>()]["bufferView"]);
  };
  const std::string pos = accessor_view("POSITION"), nor = accessor_view("NORMAL"),
                    uv1 = accessor_view("TEXCOORD_1");
  const size_t n = mesh.positions.size();
  ASSERT_EQ(pos.size(), n * 8);
  // Decoded as a glTF reader does; each matched to the nearest input vertex.
  std::vector<size_t> source(n);
  const double step = scale / 32767.0;
  double worst = 0.0, worst_normal = 1.0, worst_uv = 0.0;
  for (size_t v = 0; v < n; ++v) {
    int16_t q[4];
    std::memcpy(q, pos.data() + 8 * v, 8);
    const Vec3 p = origin + scale * Vec3(q[0], q[1], q[2]) / 32767.0;
    size_t best = 0;
    for (size_t k = 1; k < n; ++k) {
      if ((mesh.positions[k] - p).norm() < (mesh.positions[best] - p).norm()) best = k;
    }
    source[v] = best;
    worst = std::max(worst, (mesh.positions[best] - p).cwiseAbs().maxCoeff());
    const auto* nq = reinterpret_cast<const int8_t*>(nor.data() + 4 * v);
    const Vec3 normal = Vec3(nq[0], nq[1], nq[2]).normalized();
    worst_normal = std::min(worst_normal, normal.dot(mesh.normals[best]));
    float t[2];
    std::memcpy(t, uv1.data() + 8 * v, 8);
    worst_uv = std::max(worst_uv, std::abs(t[0] - mesh.uv1[best].x()));
  }
  EXPECT_LE(worst, 0.5 * step * (1 + 1e-6)) << "half a step of the 14-bit grid";
  EXPECT_GT(worst_normal, 0.999) << "8-bit octahedral normals";
  EXPECT_LT(worst_uv, 1e-6);
  // Every vertex once, and the triangles (with their winding) the input's.
  EXPECT_EQ(std::set<size_t>(source.begin(), source.end()).size(), n);
  std::set<std::array<size_t, 3>> in, out;
  auto canonical = [](std::array<size_t, 3> t) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    return t;
  };
  for (const auto& t : mesh.triangles) in.insert(canonical({t[0], t[1], t[2]}));
  for (const json& prim : g.doc["meshes"][0]["primitives"]) {
    const std::string idx =
        ViewBytes(g, g.doc["accessors"][prim["indices"].get<int>()]["bufferView"]);
    for (size_t k = 0; k + 12 <= idx.size(); k += 12) {
      uint32_t t[3];
      std::memcpy(t, idx.data() + k, 12);
      out.insert(canonical({source[t[0]], source[t[1]], source[t[2]]}));
    }
  }
  EXPECT_EQ(out, in);
}

TEST(QuantizedGlb, AKeptOrderGivesTheSameBytesAndOneThatDoesNotFitIsIgnored) {
  const Mesh mesh = Everything();
  ExportOptions o;
  o.glb = GlbEncoding::kMeshopt;
  const auto fresh = ExportMesh(mesh, MeshFormat::kGlb, o);
  ASSERT_TRUE(fresh.ok());
  auto order = ComputeMeshoptOrder(mesh);
  ASSERT_TRUE(order.ok());
  o.meshopt_order = std::make_shared<const MeshoptOrder>(std::move(*order));
  const auto kept = ExportMesh(mesh, MeshFormat::kGlb, o);
  ASSERT_TRUE(kept.ok());
  EXPECT_EQ(*kept, *fresh);
  // Another mesh's order (fewer vertices) is not used.
  const Mesh small = testing::FlatGrid(-1, -1, 2, 2, 4, 4, 0.0);
  ExportOptions plain;
  plain.glb = GlbEncoding::kMeshopt;
  const auto expected = ExportMesh(small, MeshFormat::kGlb, plain);
  const auto with_wrong = ExportMesh(small, MeshFormat::kGlb, o);
  ASSERT_TRUE(expected.ok() && with_wrong.ok());
  EXPECT_EQ(*with_wrong, *expected);
}

}  // namespace
}  // namespace surfdeform
