// GLB export (see gltf_io.hpp).
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <sstream>
#include <thread>

#include "engine/common/parallel.hpp"
#include "meshio/draco_io.hpp"
#include "meshio/gltf_io.hpp"
#include "meshio/gltf_look.hpp"
#include "meshio/gltf_model.hpp"
#include "meshio/importers.hpp"

namespace surfdeform::meshio {

int AddView(tinygltf::Model* m, const void* data, size_t bytes, int target) {
  std::vector<unsigned char>& buf = m->buffers[0].data;
  while (buf.size() % 4 != 0) buf.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.byteLength = bytes;
  view.target = target;
  if (data == nullptr) {
    buf.resize(buf.size() + bytes);  // zeros, for the caller to fill
  } else {
    const auto* p = static_cast<const unsigned char*>(data);
    buf.insert(buf.end(), p, p + bytes);
  }
  m->bufferViews.push_back(view);
  return static_cast<int>(m->bufferViews.size()) - 1;
}

int AddAccessor(tinygltf::Model* m, int view, int component, int type, size_t count,
                std::vector<double> min, std::vector<double> max) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = component;
  a.type = type;
  a.count = count;
  a.minValues = std::move(min);
  a.maxValues = std::move(max);
  m->accessors.push_back(a);
  return static_cast<int>(m->accessors.size()) - 1;
}

namespace {

// Accessors of the vertex attributes; POSITION gets the min/max glTF requires.
// With view < 0 (Draco), accessors carry no buffer view.
std::map<std::string, int> AddAttributes(tinygltf::Model* m, const Mesh& mesh, bool with_data) {
  std::map<std::string, int> attrs;
  const size_t n = mesh.positions.size();
  auto add = [&](const std::string& name, const std::vector<float>& data, int type, int comps,
                 std::vector<double> min = {}, std::vector<double> max = {}) {
    const int view =
        with_data ? AddView(m, data.data(), data.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER) : -1;
    (void)comps;
    attrs[name] = AddAccessor(m, view, TINYGLTF_COMPONENT_TYPE_FLOAT, type, n, std::move(min),
                              std::move(max));
  };
  const std::vector<float> pos = Floats(mesh.positions, 3);
  std::vector<double> lo(3, 0.0), hi(3, 0.0);
  for (int c = 0; c < 3; ++c) {
    float a = n ? pos[c] : 0.f, b = a;
    for (size_t k = 0; k < n; ++k) {
      a = std::min(a, pos[3 * k + c]);
      b = std::max(b, pos[3 * k + c]);
    }
    lo[c] = a;
    hi[c] = b;
  }
  add("POSITION", pos, TINYGLTF_TYPE_VEC3, 3, lo, hi);
  if (!mesh.normals.empty()) add("NORMAL", Floats(mesh.normals, 3), TINYGLTF_TYPE_VEC3, 3);
  if (!mesh.tangents.empty()) add("TANGENT", Floats(mesh.tangents, 4), TINYGLTF_TYPE_VEC4, 4);
  if (!mesh.uv0.empty()) add("TEXCOORD_0", Floats(mesh.uv0, 2), TINYGLTF_TYPE_VEC2, 2);
  if (!mesh.uv1.empty()) add("TEXCOORD_1", Floats(mesh.uv1, 2), TINYGLTF_TYPE_VEC2, 2);
  if (!mesh.colors.empty()) add("COLOR_0", Floats(mesh.colors, 4), TINYGLTF_TYPE_VEC4, 4);
  if (!mesh.distortion.empty()) {
    add("_DISTORTION", Floats(mesh.distortion, 2), TINYGLTF_TYPE_VEC2, 2);
  }
  return attrs;
}

// Triangles (by index) with only the vertices they use (in their original
// order), for per-primitive Draco compression.
Mesh SubMesh(const Mesh& mesh, const std::vector<uint32_t>& triangles) {
  std::vector<int64_t> remap(mesh.positions.size(), -1);
  for (uint32_t t : triangles)
    for (uint32_t v : mesh.triangles[t]) remap[v] = 0;
  Mesh sub;
  for (size_t v = 0; v < remap.size(); ++v) {
    if (remap[v] < 0) continue;
    remap[v] = static_cast<int64_t>(sub.positions.size());
    sub.positions.push_back(mesh.positions[v]);
    if (!mesh.normals.empty()) sub.normals.push_back(mesh.normals[v]);
    if (!mesh.tangents.empty()) sub.tangents.push_back(mesh.tangents[v]);
    if (!mesh.uv0.empty()) sub.uv0.push_back(mesh.uv0[v]);
    if (!mesh.uv1.empty()) sub.uv1.push_back(mesh.uv1[v]);
    if (!mesh.colors.empty()) sub.colors.push_back(mesh.colors[v]);
    if (!mesh.distortion.empty()) sub.distortion.push_back(mesh.distortion[v]);
  }
  for (uint32_t t : triangles) {
    const auto& tri = mesh.triangles[t];
    sub.triangles.push_back({static_cast<uint32_t>(remap[tri[0]]),
                             static_cast<uint32_t>(remap[tri[1]]),
                             static_cast<uint32_t>(remap[tri[2]])});
  }
  return sub;
}

// A piece of a group for Draco: its triangles.
struct Piece {
  size_t group = 0;
  std::vector<uint32_t> triangles;
};

// The group's triangles cut into `pieces` (a power of two) at the median
// of their centroids along the longest side of their box, recursively:
// compact pieces, whose borders are short. The halves are cut on their own
// threads when `threads` allows; the pieces are the same either way.
// `centroids` are the triangles' (3x their centroid), by triangle - `base`.
void SplitSpatially(const std::vector<Vec3>& centroids, uint32_t base,
                    std::vector<uint32_t> triangles, int pieces, int threads,
                    std::vector<std::vector<uint32_t>>* out) {
  if (pieces <= 1 || triangles.size() < 2) {
    out->push_back(std::move(triangles));
    return;
  }
  auto centroid = [&](uint32_t t) -> const Vec3& { return centroids[t - base]; };
  Vec3 lo = centroid(triangles[0]), hi = lo;
  for (uint32_t t : triangles) {
    lo = lo.cwiseMin(centroid(t));
    hi = hi.cwiseMax(centroid(t));
  }
  Eigen::Index axis = 0;
  (hi - lo).maxCoeff(&axis);
  // The median from a histogram of the coordinates (to a bin of 1/4096 of
  // the extent), then one pass that keeps each half in the triangles' order
  // (Draco's traversal starts from it): linear, where a sort is not.
  constexpr int kBins = 4096;
  const double from = lo[axis], extent = hi[axis] - lo[axis];
  std::vector<uint16_t> bins(triangles.size());
  std::vector<size_t> counts(kBins, 0);
  for (size_t k = 0; k < triangles.size(); ++k) {
    const double x = extent > 0.0 ? (centroid(triangles[k])[axis] - from) / extent : 0.0;
    bins[k] = static_cast<uint16_t>(std::min(kBins - 1, static_cast<int>(x * kBins)));
    ++counts[bins[k]];
  }
  int cut = 0;  // bins below `cut` go first
  for (size_t below = 0; cut < kBins && below + counts[cut] <= triangles.size() / 2; ++cut) {
    below += counts[cut];
  }
  if (cut == 0) cut = 1;  // never an empty first half
  std::vector<uint32_t> first, second;
  first.reserve(triangles.size() / 2 + 1);
  second.reserve(triangles.size() / 2 + 1);
  for (size_t k = 0; k < triangles.size(); ++k) {
    (bins[k] < cut ? first : second).push_back(triangles[k]);
  }
  if (second.empty()) {  // every centroid in one bin: halves by count
    second.assign(first.begin() + static_cast<long>(first.size() / 2), first.end());
    first.resize(first.size() / 2);
  }
  std::vector<uint32_t>().swap(triangles);
  std::vector<std::vector<uint32_t>> later;
  if (threads > 1) {
    std::thread other([&] {
      SplitSpatially(centroids, base, std::move(second), pieces / 2, threads - threads / 2, &later);
    });
    SplitSpatially(centroids, base, std::move(first), pieces / 2, threads / 2, out);
    other.join();
  } else {
    SplitSpatially(centroids, base, std::move(first), pieces / 2, 1, out);
    SplitSpatially(centroids, base, std::move(second), pieces / 2, 1, &later);
  }
  for (std::vector<uint32_t>& piece : later) out->push_back(std::move(piece));
}

}  // namespace

void AddLook(tinygltf::Model* m, const GltfLook& look) {
  std::vector<int> image_index(look.images.size(), -1);
  for (size_t k = 0; k < look.images.size(); ++k) {
    const std::string& bytes = look.image_bytes[k];
    if (bytes.empty()) continue;
    tinygltf::Image image = look.images[k];
    image.name = CleanName(image.name);
    image.bufferView = AddView(m, bytes.data(), bytes.size(), 0);
    image_index[k] = static_cast<int>(m->images.size());
    m->images.push_back(std::move(image));
  }
  for (tinygltf::Texture t : look.textures) {
    t.name = CleanName(t.name);
    t.source = t.source >= 0 && static_cast<size_t>(t.source) < image_index.size()
                   ? image_index[t.source]
                   : -1;
    m->textures.push_back(std::move(t));
  }
  for (tinygltf::Sampler s : look.samplers) {
    s.name = CleanName(s.name);
    m->samplers.push_back(std::move(s));
  }
  for (tinygltf::Material mat : look.materials) {
    mat.name = CleanName(mat.name);
    m->materials.push_back(std::move(mat));
  }
  for (const std::string& ext : look.extensions) m->extensionsUsed.push_back(ext);
}

void AddMaterials(tinygltf::Model* m, const ExportOptions& o) {
  if (o.look != nullptr) {
    AddLook(m, *o.look);
    return;
  }
  for (const std::string& name : o.materials) {
    tinygltf::Material mat;
    mat.name = name;
    m->materials.push_back(mat);
  }
}

Result<std::string> WriteGlb(const Mesh& mesh, const ExportOptions& o) {
  if (o.glb == GlbEncoding::kMeshopt || o.glb == GlbEncoding::kQuantized) {
    return WriteQuantizedGlb(mesh, o, o.glb == GlbEncoding::kMeshopt);
  }
  const bool draco = o.glb == GlbEncoding::kDraco;
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "surfdeform";
  m.buffers.resize(1);
  std::vector<MeshGroup> groups = mesh.groups;
  if (groups.empty())
    groups.push_back({"mesh", -1, 0, static_cast<uint32_t>(mesh.triangles.size())});
  AddMaterials(&m, o);
  tinygltf::Mesh gm;
  gm.name = groups.front().name.empty() ? "mesh" : groups.front().name;
  auto primitive_of = [&m](const MeshGroup& g) {
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material =
        g.material >= 0 && g.material < static_cast<int>(m.materials.size()) ? g.material : -1;
    return prim;
  };
  if (!draco) {
    const std::map<std::string, int> shared = AddAttributes(&m, mesh, true);
    for (const MeshGroup& g : groups) {
      tinygltf::Primitive prim = primitive_of(g);
      prim.attributes = shared;
      std::vector<uint32_t> idx;
      idx.reserve(3 * g.triangle_count);
      for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t)
        for (uint32_t v : mesh.triangles[t]) idx.push_back(v);
      const int view =
          AddView(&m, idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
      prim.indices = AddAccessor(&m, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                 TINYGLTF_TYPE_SCALAR, idx.size());
      gm.primitives.push_back(prim);
    }
  } else {
    // One Draco primitive per group, or past o.split_vertices per piece of
    // it, the pieces on one quantization grid and encoded in parallel.
    const int pieces = GlbPieces(mesh.positions.size(), o.split_vertices);
    const int threads = std::max(1, o.threads);
    std::vector<Piece> parts;
    for (size_t k = 0; k < groups.size(); ++k) {
      const MeshGroup& g = groups[k];
      std::vector<uint32_t> triangles(g.triangle_count);
      std::vector<Vec3> centroids(pieces > 1 ? g.triangle_count : 0);
      ParallelChunks(static_cast<int>(g.triangle_count), pieces > 1 ? threads : 1,
                     [&](int, int begin, int end) {
                       for (int t = begin; t < end; ++t) {
                         triangles[t] = g.first_triangle + static_cast<uint32_t>(t);
                         if (pieces == 1) continue;
                         const auto& tri = mesh.triangles[triangles[t]];
                         centroids[t] = mesh.positions[tri[0]] + mesh.positions[tri[1]] +
                                        mesh.positions[tri[2]];
                       }
                     });
      std::vector<std::vector<uint32_t>> split;
      SplitSpatially(centroids, g.first_triangle, std::move(triangles), pieces, threads, &split);
      for (std::vector<uint32_t>& piece : split) parts.push_back({k, std::move(piece)});
    }
    const DracoGrid grid = DracoGridOf(mesh);
    const DracoGrid* shared_grid = pieces > 1 ? &grid : nullptr;
    const int n = static_cast<int>(parts.size());
    std::vector<Mesh> subs(parts.size());
    std::vector<std::array<int, kGltfDracoAttributes>> ids(parts.size());
    std::vector<Result<std::string>> encoded(parts.size(), Status(ErrorCode::kInternal, "unset"));
    ParallelChunks(n, threads, [&](int, int begin, int end) {
      for (int p = begin; p < end; ++p) {
        subs[p] = SubMesh(mesh, parts[p].triangles);
        encoded[p] = EncodeDraco(subs[p], o.draco, ids[p].data(), shared_grid);
      }
    });
    for (int p = 0; p < n; ++p) {
      SURFDEFORM_RETURN_IF_ERROR(encoded[p].status());
      const Mesh& sub = subs[p];
      tinygltf::Primitive prim = primitive_of(groups[parts[p].group]);
      // Accessors describe the decoded data and have no buffer view.
      prim.attributes = AddAttributes(&m, sub, false);
      prim.indices = AddAccessor(&m, -1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                 sub.triangles.size() * 3);
      const int view = AddView(&m, encoded[p]->data(), encoded[p]->size(), 0);
      tinygltf::Value::Object attrs;
      for (int k = 0; k < kGltfDracoAttributes; ++k) {
        if (ids[p][k] >= 0) attrs[kGltfDracoNames[k]] = tinygltf::Value(ids[p][k]);
      }
      tinygltf::Value::Object ext;
      ext["bufferView"] = tinygltf::Value(view);
      ext["attributes"] = tinygltf::Value(attrs);
      prim.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(ext);
      gm.primitives.push_back(prim);
    }
  }
  if (draco) {
    m.extensionsUsed.push_back("KHR_draco_mesh_compression");
    m.extensionsRequired.push_back("KHR_draco_mesh_compression");
  }
  m.meshes.push_back(gm);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = gm.name;
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  m.buffers[0].data.resize((m.buffers[0].data.size() + 3) / 4 * 4, 0);
  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  if (!writer.WriteGltfSceneToStream(&m, out, false, true)) {
    return Status(ErrorCode::kInternal, "GLB writing failed");
  }
  return out.str();
}

}  // namespace surfdeform::meshio
