// GLB of one mesh with quantized attributes (KHR_mesh_quantization), its
// buffer views compressed with EXT_meshopt_compression or not (see
// gltf_io.hpp, WriteQuantizedGlb).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <meshoptimizer.h>

#include "meshio/gltf_io.hpp"
#include "meshio/gltf_model.hpp"
#include "meshio/meshopt_views.hpp"

namespace surfdeform::meshio {
namespace {

// Positions as 14-bit integers (Draco's default precision, and gltfpack's)
// over the mesh's bounding box, stored as 16-bit normalized ones: the
// integer q stands for origin + q * step, |q| <= 8191, so the node's
// translation (origin) and uniform scale (32767 * step) undo it.
constexpr double kPositionSteps = 16382.0;  // 2^14 - 2: q from -8191 to 8191

struct PositionGrid {
  Vec3 origin = Vec3::Zero();
  double step = 1.0;

  explicit PositionGrid(const std::vector<Vec3>& positions) {
    if (positions.empty()) return;
    Vec3 lo = positions.front(), hi = lo;
    for (const Vec3& p : positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    origin = 0.5 * (lo + hi);
    const double side = (hi - lo).maxCoeff();
    if (side > 0.0) step = side / kPositionSteps;
  }
  int16_t At(double x, int c) const {
    const double q = std::round((x - origin[c]) / step);
    return static_cast<int16_t>(std::clamp(q, -8191.0, 8191.0));
  }
};

uint8_t Unorm8(double x) {
  return static_cast<uint8_t>(std::clamp(std::round(x * 255.0), 0.0, 255.0));
}
uint16_t Unorm16(double x) {
  return static_cast<uint16_t>(std::clamp(std::round(x * 65535.0), 0.0, 65535.0));
}

template <typename V>
std::vector<V> InOrder(const std::vector<V>& values, const std::vector<uint32_t>& order) {
  std::vector<V> out(order.size());
  for (size_t v = 0; v < order.size(); ++v) out[v] = values[order[v]];
  return out;
}

bool AllInUnitSquare(const std::vector<Vec2>& uv) {
  return std::all_of(uv.begin(), uv.end(), [](const Vec2& t) {
    return t.x() >= 0.0 && t.x() <= 1.0 && t.y() >= 0.0 && t.y() <= 1.0;
  });
}

std::vector<MeshGroup> GroupsOf(const Mesh& mesh) {
  if (!mesh.groups.empty()) return mesh.groups;
  return {{"mesh", -1, 0, static_cast<uint32_t>(mesh.triangles.size())}};
}

// The order fits the mesh: a vertex order and triangle counts of its own.
bool Fits(const MeshoptOrder& order, const Mesh& mesh, const std::vector<MeshGroup>& groups) {
  if (order.vertex.size() != mesh.positions.size() || order.indices.size() != groups.size()) {
    return false;
  }
  for (size_t k = 0; k < groups.size(); ++k) {
    if (order.indices[k].size() != 3 * size_t{groups[k].triangle_count}) return false;
  }
  return true;
}

// The model, its buffer views and how each is compressed.
class Builder {
 public:
  Builder() {
    m_.asset.version = "2.0";
    m_.asset.generator = "surfdeform";
    m_.buffers.resize(1);
  }

  // A vertex attribute of `count` elements of `stride` bytes (compressed
  // as `codec`, when it has a filter).
  int Attribute(const void* data, size_t count, int stride, int component, int type,
                bool normalized, std::vector<double> min = {}, std::vector<double> max = {},
                ViewCodec codec = {}) {
    const int view =
        AddView(&m_, data, count * static_cast<size_t>(stride), TINYGLTF_TARGET_ARRAY_BUFFER);
    m_.bufferViews[view].byteStride = static_cast<size_t>(stride);
    codec.mode = ViewCodec::Mode::kAttributes;
    codec.stride = stride;
    Codec(view, std::move(codec));
    const int a = AddAccessor(&m_, view, component, type, count, std::move(min), std::move(max));
    m_.accessors[a].normalized = normalized;
    return a;
  }

  int Triangles(const std::vector<uint32_t>& idx) {
    const int view = AddView(&m_, idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    Codec(view, {ViewCodec::Mode::kTriangles, 4});
    return AddAccessor(&m_, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                       idx.size());
  }

  tinygltf::Model& model() { return m_; }
  std::vector<ViewCodec> TakeCodecs() { return std::move(codecs_); }

 private:
  void Codec(int view, ViewCodec codec) {
    codecs_.resize(m_.bufferViews.size());
    codecs_[static_cast<size_t>(view)] = std::move(codec);
  }

  tinygltf::Model m_;
  std::vector<ViewCodec> codecs_;
};

// POSITION, NORMAL, TANGENT, TEXCOORD_n, COLOR_0 and _DISTORTION, quantized
// as KHR_mesh_quantization allows (texture coordinates outside [0, 1] and
// the distortion stay floats).
std::map<std::string, int> AddQuantizedAttributes(Builder* b, const Mesh& mesh,
                                                  const std::vector<uint32_t>& order,
                                                  const PositionGrid& grid) {
  std::map<std::string, int> attrs;
  const size_t n = mesh.positions.size();
  {
    std::vector<std::array<int16_t, 4>> q(n, {0, 0, 0, 0});
    std::vector<double> lo(3, 0.0), hi(3, 0.0);
    for (size_t v = 0; v < n; ++v) {
      for (int c = 0; c < 3; ++c) {
        q[v][c] = grid.At(mesh.positions[order[v]][c], c);
        lo[c] = v == 0 ? q[v][c] : std::min<double>(lo[c], q[v][c]);
        hi[c] = v == 0 ? q[v][c] : std::max<double>(hi[c], q[v][c]);
      }
    }
    attrs["POSITION"] = b->Attribute(q.data(), n, 8, TINYGLTF_COMPONENT_TYPE_SHORT,
                                     TINYGLTF_TYPE_VEC3, true, std::move(lo), std::move(hi));
  }
  // Unit vectors (and a tangent's sign in w): octahedral, 8 bits
  // (meshoptimizer's OCTAHEDRAL filter); the view holds what the filter
  // decodes to, 8-bit normalized integers.
  auto octahedral = [&](const char* name, const auto& values, int type, bool with_w) {
    std::vector<float> f(4 * n, 0.0f);
    for (size_t v = 0; v < n; ++v) {
      const auto& x = values[order[v]];
      for (int c = 0; c < 3; ++c) f[4 * v + c] = static_cast<float>(x[c]);
      f[4 * v + 3] = with_w ? static_cast<float>(x[3]) : 0.0f;
    }
    ViewCodec codec;
    codec.filter = "OCTAHEDRAL";
    codec.filtered.resize(4 * n);
    if (n > 0) meshopt_encodeFilterOct(codec.filtered.data(), n, 4, 8, f.data());
    std::vector<unsigned char> decoded = codec.filtered;
    if (n > 0) meshopt_decodeFilterOct(decoded.data(), n, 4);
    attrs[name] = b->Attribute(decoded.data(), n, 4, TINYGLTF_COMPONENT_TYPE_BYTE, type, true, {},
                               {}, std::move(codec));
  };
  if (!mesh.normals.empty()) octahedral("NORMAL", mesh.normals, TINYGLTF_TYPE_VEC3, false);
  if (!mesh.tangents.empty()) octahedral("TANGENT", mesh.tangents, TINYGLTF_TYPE_VEC4, true);
  auto uv = [&](const char* name, const std::vector<Vec2>& values) {
    if (values.empty()) return;
    if (AllInUnitSquare(values)) {
      std::vector<std::array<uint16_t, 2>> q(n);
      for (size_t v = 0; v < n; ++v) {
        const Vec2& t = values[order[v]];
        q[v] = {Unorm16(t.x()), Unorm16(t.y())};
      }
      attrs[name] = b->Attribute(q.data(), n, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                 TINYGLTF_TYPE_VEC2, true);
    } else {
      const std::vector<float> f = Floats(InOrder(values, order), 2);
      attrs[name] =
          b->Attribute(f.data(), n, 8, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, false);
    }
  };
  uv("TEXCOORD_0", mesh.uv0);
  uv("TEXCOORD_1", mesh.uv1);
  if (!mesh.colors.empty()) {
    std::vector<std::array<uint8_t, 4>> q(n);
    for (size_t v = 0; v < n; ++v)
      for (int c = 0; c < 4; ++c) q[v][c] = Unorm8(mesh.colors[order[v]][c]);
    attrs["COLOR_0"] = b->Attribute(q.data(), n, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                    TINYGLTF_TYPE_VEC4, true);
  }
  if (!mesh.distortion.empty()) {
    const std::vector<float> f = Floats(InOrder(mesh.distortion, order), 2);
    attrs["_DISTORTION"] =
        b->Attribute(f.data(), n, 8, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, false);
  }
  return attrs;
}

}  // namespace

Result<std::string> WriteQuantizedGlb(const Mesh& mesh, const ExportOptions& o, bool compress) {
  Builder b;
  tinygltf::Model& m = b.model();
  const std::vector<MeshGroup> groups = GroupsOf(mesh);
  std::shared_ptr<const MeshoptOrder> order = o.meshopt_order;
  if (order == nullptr || !Fits(*order, mesh, groups)) {
    SURFDEFORM_ASSIGN_OR_RETURN(MeshoptOrder computed, ComputeMeshoptOrder(mesh));
    order = std::make_shared<const MeshoptOrder>(std::move(computed));
  }
  const PositionGrid grid(mesh.positions);
  const std::map<std::string, int> attrs = AddQuantizedAttributes(&b, mesh, order->vertex, grid);
  AddMaterials(&m, o);
  tinygltf::Mesh gm;
  gm.name = groups.front().name.empty() ? "mesh" : groups.front().name;
  for (size_t k = 0; k < groups.size(); ++k) {
    const MeshGroup& g = groups[k];
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material =
        g.material >= 0 && g.material < static_cast<int>(m.materials.size()) ? g.material : -1;
    prim.attributes = attrs;
    prim.indices = b.Triangles(order->indices[k]);
    gm.primitives.push_back(prim);
  }
  m.meshes.push_back(gm);
  AddQuantizedNode(&m, gm.name, {grid.origin.x(), grid.origin.y(), grid.origin.z()},
                   grid.step * 32767.0);
  SURFDEFORM_ASSIGN_OR_RETURN(BuiltGlb built, Finish(&m, b.TakeCodecs()));
  if (!compress) return Glb(built.doc, built.bin_view());
  return Compress(std::move(built), std::max(1, o.threads));
}

}  // namespace surfdeform::meshio

namespace surfdeform {

Result<MeshoptOrder> ComputeMeshoptOrder(const Mesh& mesh) {
  const std::vector<MeshGroup> groups = meshio::GroupsOf(mesh);
  const size_t n = mesh.positions.size();
  MeshoptOrder order;
  std::vector<uint32_t> all;
  all.reserve(3 * mesh.triangles.size());
  for (const MeshGroup& g : groups) {
    std::vector<uint32_t> idx;
    idx.reserve(3 * size_t{g.triangle_count});
    for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t)
      for (uint32_t v : mesh.triangles[t]) idx.push_back(v);
    std::vector<uint32_t> cached(idx.size());
    meshopt_optimizeVertexCache(cached.data(), idx.data(), idx.size(), n);
    all.insert(all.end(), cached.begin(), cached.end());
    order.indices.push_back(std::move(cached));
  }
  std::vector<uint32_t> remap(n);
  uint32_t next = static_cast<uint32_t>(
      meshopt_optimizeVertexFetchRemap(remap.data(), all.data(), all.size(), n));
  for (uint32_t& r : remap) {
    if (r == ~0u) r = next++;
  }
  order.vertex.resize(n);
  for (size_t v = 0; v < n; ++v) order.vertex[remap[v]] = static_cast<uint32_t>(v);
  for (std::vector<uint32_t>& idx : order.indices) {
    for (uint32_t& v : idx) v = remap[v];
    SURFDEFORM_RETURN_IF_ERROR(meshio::AsTheCodecDecodes(&idx));
  }
  return order;
}

size_t MeshoptOrder::bytes() const {
  size_t total = sizeof(*this) + vertex.size() * sizeof(uint32_t);
  for (const std::vector<uint32_t>& idx : indices) total += idx.size() * sizeof(uint32_t) + 24;
  return total;
}

}  // namespace surfdeform
