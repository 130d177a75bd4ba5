// GLB export (see gltf_io.hpp).
#include <tiny_gltf.h>

#include <cstring>
#include <sstream>

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

// The triangles of one group with only the vertices they use (in their
// original order), for per-primitive Draco compression.
Mesh SubMesh(const Mesh& mesh, const MeshGroup& g) {
  std::vector<int64_t> remap(mesh.positions.size(), -1);
  for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t)
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
  for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t) {
    const auto& tri = mesh.triangles[t];
    sub.triangles.push_back({static_cast<uint32_t>(remap[tri[0]]),
                             static_cast<uint32_t>(remap[tri[1]]),
                             static_cast<uint32_t>(remap[tri[2]])});
  }
  return sub;
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
  std::map<std::string, int> shared;
  if (!draco) shared = AddAttributes(&m, mesh, true);
  for (const MeshGroup& g : groups) {
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material =
        g.material >= 0 && g.material < static_cast<int>(m.materials.size()) ? g.material : -1;
    if (!draco) {
      prim.attributes = shared;
      std::vector<uint32_t> idx;
      idx.reserve(3 * g.triangle_count);
      for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t)
        for (uint32_t v : mesh.triangles[t]) idx.push_back(v);
      const int view =
          AddView(&m, idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
      prim.indices = AddAccessor(&m, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                 TINYGLTF_TYPE_SCALAR, idx.size());
    } else {
      const Mesh sub = SubMesh(mesh, g);
      int ids[kGltfDracoAttributes];
      SURFDEFORM_ASSIGN_OR_RETURN(auto encoded, EncodeDraco(sub, o.draco, ids));
      // Accessors describe the decoded data and have no buffer view.
      prim.attributes = AddAttributes(&m, sub, false);
      prim.indices = AddAccessor(&m, -1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                 sub.triangles.size() * 3);
      const int view = AddView(&m, encoded.data(), encoded.size(), 0);
      tinygltf::Value::Object attrs;
      for (int k = 0; k < kGltfDracoAttributes; ++k) {
        if (ids[k] >= 0) attrs[kGltfDracoNames[k]] = tinygltf::Value(ids[k]);
      }
      tinygltf::Value::Object ext;
      ext["bufferView"] = tinygltf::Value(view);
      ext["attributes"] = tinygltf::Value(attrs);
      prim.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(ext);
    }
    gm.primitives.push_back(prim);
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
