// glTF 2.0 and GLB import (see gltf_io.hpp for the safety measures).
#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <unordered_set>

#include "base/format.hpp"
#include "json/bounded_json.hpp"
#include "meshio/draco_io.hpp"
#include "meshio/gltf_io.hpp"
#include "meshio/gltf_look.hpp"
#include "meshio/gltf_schema.hpp"
#include "meshio/importers.hpp"

namespace surfdeform::meshio {
namespace {

using Mat4 = Eigen::Matrix4d;

Status GltfError(const std::string& what) { return InvalidArgument("glTF: " + what, "mesh"); }

// --- tinygltf callbacks: nothing from the file system, no image decoding ---
bool RefuseExists(const std::string&, void*) { return false; }
std::string RefuseExpand(const std::string&, void*) { return {}; }
bool RefuseRead(std::vector<unsigned char>*, std::string* err, const std::string&, void*) {
  if (err != nullptr) *err = "external files are not read";
  return false;
}
bool RefuseWrite(std::string*, const std::string&, const std::vector<unsigned char>&, void*) {
  return false;
}
// Images are never decoded: the loader keeps each image's bytes as they are
// (from its buffer view or its data: URI), by image index.
struct ImageSink {
  const tinygltf::Model* model = nullptr;  // the one being loaded: its buffers are in
  std::vector<std::string> kept;
};
bool KeepImageBytes(tinygltf::Image* image, const int index, std::string* err, std::string*, int,
                    int, const unsigned char* bytes, int size, void* user) {
  auto* sink = static_cast<ImageSink*>(user);
  if (index < 0 || bytes == nullptr || size <= 0) return true;
  // tinygltf 2.7.0 hands over a buffer view's bytes without checking the view
  // against its buffer (found by tests/fuzz, import target): check it here,
  // before reading one byte.
  if (image != nullptr && image->bufferView >= 0) {
    const auto& views = sink->model->bufferViews;
    const size_t v = static_cast<size_t>(image->bufferView);
    const bool fits = v < views.size() && views[v].buffer >= 0 &&
                      static_cast<size_t>(views[v].buffer) < sink->model->buffers.size() &&
                      views[v].byteOffset <= sink->model->buffers[views[v].buffer].data.size() &&
                      static_cast<size_t>(size) <=
                          sink->model->buffers[views[v].buffer].data.size() - views[v].byteOffset;
    if (!fits) {
      if (err != nullptr) *err += "an image's buffer view runs past its buffer\n";
      return false;
    }
  }
  if (static_cast<size_t>(index) >= sink->kept.size()) {
    sink->kept.resize(static_cast<size_t>(index) + 1);
  }
  sink->kept[index].assign(reinterpret_cast<const char*>(bytes), static_cast<size_t>(size));
  return true;
}

// The input's materials, textures, samplers and images for glTF output
// (gltf_look.hpp): images by their bytes, of a type their magic bytes show.
Result<std::shared_ptr<const GltfLook>> LookOf(const tinygltf::Model& model,
                                               std::vector<std::string> image_bytes,
                                               const ImportLimits& limits,
                                               std::vector<std::string>* warnings) {
  if (model.materials.empty()) return std::shared_ptr<const GltfLook>();
  auto look = std::make_shared<GltfLook>();
  look->materials = model.materials;
  look->textures = model.textures;
  look->samplers = model.samplers;
  image_bytes.resize(model.images.size());
  size_t total = 0, dropped = 0;
  for (size_t k = 0; k < model.images.size(); ++k) {
    tinygltf::Image image;
    image.name = model.images[k].name;
    const std::string_view type = ImageMediaType(image_bytes[k]);
    if (type.empty()) {
      ++dropped;
      image_bytes[k].clear();
    } else {
      image.mimeType = std::string(type);
      total += image_bytes[k].size();
    }
    look->images.push_back(std::move(image));
  }
  if (total > limits.max_image_bytes) {
    return Status::LimitExceeded(
        "glTF: the embedded images hold " + std::to_string(total) + " bytes; the limit is " +
            std::to_string(limits.max_image_bytes),
        "mesh", static_cast<double>(limits.max_image_bytes), static_cast<double>(total));
  }
  if (dropped > 0) {
    warnings->push_back("dropped " + std::to_string(dropped) +
                        " images that are not embedded PNG or JPEG (by their bytes)");
  }
  look->image_bytes = std::move(image_bytes);
  for (const std::string& ext : model.extensionsUsed) {
    if (ext.rfind("KHR_materials_", 0) == 0 || ext == "KHR_texture_transform") {
      look->extensions.push_back(ext);
    }
  }
  return std::shared_ptr<const GltfLook>(std::move(look));
}

// The JSON chunk of a GLB (bounds-checked), or the text itself.
Status JsonOf(std::string_view bytes, bool binary, std::string_view* json) {
  if (!binary) {
    *json = bytes;
    return Status::Ok();
  }
  if (bytes.size() < 20) return GltfError("the GLB header is truncated");
  uint32_t total, chunk_length, chunk_type;
  std::memcpy(&total, bytes.data() + 8, 4);
  std::memcpy(&chunk_length, bytes.data() + 12, 4);
  std::memcpy(&chunk_type, bytes.data() + 16, 4);
  if (total > bytes.size()) {
    return GltfError("the GLB header claims " + std::to_string(total) + " bytes; the file has " +
                     std::to_string(bytes.size()));
  }
  if (chunk_type != 0x4E4F534Au) return GltfError("the first GLB chunk is not JSON");
  if (chunk_length > total - 20) return GltfError("the JSON chunk runs past the end of the file");
  *json = bytes.substr(20, chunk_length);
  return Status::Ok();
}

Mat4 NodeMatrix(const tinygltf::Node& n) {
  Mat4 m = Mat4::Identity();
  if (n.matrix.size() == 16) {
    for (int k = 0; k < 16; ++k) m(k % 4, k / 4) = n.matrix[k];  // column-major
    return m;
  }
  if (n.translation.size() == 3)
    m.block<3, 1>(0, 3) = Vec3(n.translation[0], n.translation[1], n.translation[2]);
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (n.rotation.size() == 4) {
    r = Eigen::Quaterniond(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2])
            .normalized()
            .toRotationMatrix();
  }
  Vec3 s(1, 1, 1);
  if (n.scale.size() == 3) s = Vec3(n.scale[0], n.scale[1], n.scale[2]);
  m.block<3, 3>(0, 0) = r * s.asDiagonal();
  return m;
}

// Reads an accessor as doubles, `comps` per element, applying the glTF rules
// for normalized integers. Every offset, stride and count is checked against
// the buffer before any value is read.
Status ReadAccessor(const tinygltf::Model& model, int index, const char* what, int comps,
                    const ImportLimits& limits, std::vector<double>* out, size_t* count_out) {
  const std::string where = std::string(what) + " (accessor " + std::to_string(index) + ")";
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) {
    return GltfError(where + " does not exist");
  }
  const tinygltf::Accessor& a = model.accessors[index];
  if (a.sparse.isSparse) return GltfError(where + ": sparse accessors are not supported");
  const int ncomp = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
  if (ncomp != comps || csize <= 0) {
    return GltfError(where + " has " + std::to_string(ncomp) +
                     " components of an unsupported "
                     "type; " +
                     std::to_string(comps) + " expected");
  }
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("accessor elements", a.count, limits.max_triangles * 3));
  if (a.bufferView < 0 || a.bufferView >= static_cast<int>(model.bufferViews.size())) {
    return GltfError(where + " has no valid buffer view");
  }
  const tinygltf::BufferView& view = model.bufferViews[a.bufferView];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) {
    return GltfError(where + ": its buffer view has no valid buffer");
  }
  const std::vector<unsigned char>& buf = model.buffers[view.buffer].data;
  const size_t elem = static_cast<size_t>(ncomp) * csize;
  const size_t stride = view.byteStride == 0 ? elem : view.byteStride;
  if (stride < elem || stride > 252) return GltfError(where + " has an invalid byte stride");
  if (view.byteOffset > buf.size() || view.byteLength > buf.size() - view.byteOffset) {
    return GltfError(where + ": its buffer view lies past the end of its buffer");
  }
  // Overflow-safe: the last element must end inside the view.
  if (a.byteOffset > view.byteLength) return GltfError(where + " starts past its buffer view");
  const size_t avail = view.byteLength - a.byteOffset;
  if (a.count > 0 && (elem > avail || (a.count - 1) > (avail - elem) / stride)) {
    return GltfError(where + ": " + std::to_string(a.count) +
                     " elements do not fit in its buffer view");
  }
  const unsigned char* base = buf.data() + view.byteOffset + a.byteOffset;
  out->resize(a.count * comps);
  for (size_t k = 0; k < a.count; ++k) {
    const unsigned char* e = base + k * stride;
    for (int c = 0; c < comps; ++c) {
      const unsigned char* p = e + static_cast<size_t>(c) * csize;
      double v = 0;
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
          float f;
          std::memcpy(&f, p, 4);
          v = f;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
          const int8_t x = static_cast<int8_t>(*p);
          v = a.normalized ? std::max(x / 127.0, -1.0) : x;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          v = a.normalized ? *p / 255.0 : *p;
          break;
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
          int16_t x;
          std::memcpy(&x, p, 2);
          v = a.normalized ? std::max(x / 32767.0, -1.0) : x;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          uint16_t x;
          std::memcpy(&x, p, 2);
          v = a.normalized ? x / 65535.0 : x;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
          uint32_t x;
          std::memcpy(&x, p, 4);
          v = x;
          break;
        }
        default:
          return GltfError(where + " has an unsupported component type");
      }
      (*out)[k * comps + c] = v;
    }
  }
  *count_out = a.count;
  return Status::Ok();
}

// Vertex blocks already appended, by node and attribute accessors: the
// primitives of one node that share their vertex accessors (one per material,
// as our own GLB writer makes them) share their vertices too, which keeps the
// vertex order and count through a round trip.
struct SharedVertices {
  uint32_t base = 0;
  uint32_t count = 0;
};
using SharedBlocks = std::map<std::string, SharedVertices>;

std::string BlockKey(int node, const tinygltf::Primitive& prim) {
  std::string key = std::to_string(node);
  for (const auto& [name, accessor] : prim.attributes)
    key += ";" + name + "=" + std::to_string(accessor);
  return key;
}

// A KHR_draco_mesh_compression primitive, decoded into `part`.
Status DecodeDracoPrimitive(const tinygltf::Model& model, const tinygltf::Value& ext,
                            const ImportLimits& limits, Mesh* part) {
  const int view_index = ext.Get("bufferView").IsInt() ? ext.Get("bufferView").Get<int>() : -1;
  if (view_index < 0 || view_index >= static_cast<int>(model.bufferViews.size())) {
    return GltfError("a Draco primitive has no valid buffer view");
  }
  const tinygltf::BufferView& view = model.bufferViews[view_index];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()) ||
      view.byteOffset > model.buffers[view.buffer].data.size() ||
      view.byteLength > model.buffers[view.buffer].data.size() - view.byteOffset) {
    return GltfError("a Draco primitive's buffer view lies outside its buffer");
  }
  int ids[6] = {-1, -1, -1, -1, -1, -1};
  const char* names[6] = {"POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0", "TANGENT"};
  const tinygltf::Value& attrs = ext.Get("attributes");
  for (int k = 0; k < 6; ++k) {
    if (attrs.Has(names[k]) && attrs.Get(names[k]).IsInt()) ids[k] = attrs.Get(names[k]).Get<int>();
  }
  const auto* data = model.buffers[view.buffer].data.data() + view.byteOffset;
  return DecodeDraco(std::string_view(reinterpret_cast<const char*>(data), view.byteLength), limits,
                     part, ids);
}

// The accessor of a primitive's attribute; -1: none.
int AttributeOf(const tinygltf::Primitive& prim, const char* key) {
  auto it = prim.attributes.find(key);
  return it == prim.attributes.end() ? -1 : it->second;
}

// A primitive's vertex attributes (POSITION, and NORMAL, TANGENT,
// TEXCOORD_0/1, COLOR_0 where given, each of POSITION's count) into `part`.
Status ReadVertexAttributes(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                            const ImportLimits& limits, Mesh* part) {
  auto attr = [&](const char* key) { return AttributeOf(prim, key); };
  std::vector<double> v;
  size_t n = 0, m = 0;
  SURFDEFORM_RETURN_IF_ERROR(ReadAccessor(model, attr("POSITION"), "POSITION", 3, limits, &v, &n));
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("vertices", n, limits.max_vertices));
  part->positions.resize(n);
  for (size_t k = 0; k < n; ++k) part->positions[k] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
  auto same_count = [&](const char* what) {
    return m == n ? Status::Ok()
                  : GltfError(std::string(what) + " has " + std::to_string(m) +
                              " elements, POSITION " + std::to_string(n));
  };
  if (attr("NORMAL") >= 0) {
    SURFDEFORM_RETURN_IF_ERROR(ReadAccessor(model, attr("NORMAL"), "NORMAL", 3, limits, &v, &m));
    SURFDEFORM_RETURN_IF_ERROR(same_count("NORMAL"));
    part->normals.resize(n);
    for (size_t k = 0; k < n; ++k) part->normals[k] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
  }
  if (attr("TANGENT") >= 0) {
    SURFDEFORM_RETURN_IF_ERROR(ReadAccessor(model, attr("TANGENT"), "TANGENT", 4, limits, &v, &m));
    SURFDEFORM_RETURN_IF_ERROR(same_count("TANGENT"));
    part->tangents.resize(n);
    for (size_t k = 0; k < n; ++k)
      part->tangents[k] = Vec4(v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3] < 0 ? -1 : 1);
  }
  std::vector<Vec2>* uvs[2] = {&part->uv0, &part->uv1};
  for (int u = 0; u < 2; ++u) {
    const std::string key = "TEXCOORD_" + std::to_string(u);
    if (attr(key.c_str()) < 0) continue;
    SURFDEFORM_RETURN_IF_ERROR(
        ReadAccessor(model, attr(key.c_str()), key.c_str(), 2, limits, &v, &m));
    SURFDEFORM_RETURN_IF_ERROR(same_count(key.c_str()));
    uvs[u]->resize(n);
    for (size_t k = 0; k < n; ++k) (*uvs[u])[k] = Vec2(v[2 * k], v[2 * k + 1]);
  }
  if (attr("COLOR_0") >= 0) {
    const int comps = model.accessors[attr("COLOR_0")].type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
    SURFDEFORM_RETURN_IF_ERROR(
        ReadAccessor(model, attr("COLOR_0"), "COLOR_0", comps, limits, &v, &m));
    SURFDEFORM_RETURN_IF_ERROR(same_count("COLOR_0"));
    part->colors.resize(n);
    for (size_t k = 0; k < n; ++k) {
      part->colors[k] = Vec4(v[comps * k], v[comps * k + 1], v[comps * k + 2],
                             comps == 4 ? v[comps * k + 3] : 1.0);
    }
  }
  return Status::Ok();
}

// A primitive's triangles over its `n` vertices (its indices, or the
// vertices in order), from triangles, a strip or a fan; other modes add none.
Status ReadTriangles(const tinygltf::Model& model, const tinygltf::Primitive& prim, size_t n,
                     const ImportLimits& limits, Mesh* part) {
  std::vector<double> v;
  size_t m = 0;
  std::vector<uint32_t> idx;
  if (prim.indices >= 0) {
    SURFDEFORM_RETURN_IF_ERROR(ReadAccessor(model, prim.indices, "indices", 1, limits, &v, &m));
    idx.resize(m);
    for (size_t k = 0; k < m; ++k) {
      if (!(v[k] >= 0 && v[k] < static_cast<double>(n))) {
        return GltfError(Format("index %.17g of accessor %d is out of range (%zu vertices)", v[k],
                                prim.indices, n));
      }
      idx[k] = static_cast<uint32_t>(v[k]);
    }
  } else {
    idx.resize(n);
    for (size_t k = 0; k < n; ++k) idx[k] = static_cast<uint32_t>(k);
  }
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t k = 0; k + 2 < idx.size(); k += 3)
      part->triangles.push_back({idx[k], idx[k + 1], idx[k + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t k = 0; k + 2 < idx.size(); ++k) {
      if (k % 2 == 0)
        part->triangles.push_back({idx[k], idx[k + 1], idx[k + 2]});
      else
        part->triangles.push_back({idx[k + 1], idx[k], idx[k + 2]});
    }
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (size_t k = 1; k + 1 < idx.size(); ++k)
      part->triangles.push_back({idx[0], idx[k], idx[k + 1]});
  }
  return Status::Ok();
}

// The node's transform baked into `part`: normals by its inverse
// transpose, tangents by it, and the winding kept where it mirrors.
void BakeTransform(const Mat4& transform, Mesh* part) {
  const Eigen::Matrix3d linear = transform.block<3, 3>(0, 0);
  const Eigen::Matrix3d normal_linear = linear.inverse().transpose();
  for (Vec3& p : part->positions) p = linear * p + transform.block<3, 1>(0, 3);
  for (Vec3& nrm : part->normals) {
    const Vec3 t = normal_linear * nrm;
    nrm = t.norm() > 0 ? Vec3(t.normalized()) : Vec3::UnitZ();
  }
  for (Vec4& t : part->tangents) {
    const Vec3 d = linear * t.head<3>();
    t.head<3>() = d.norm() > 0 ? Vec3(d.normalized()) : Vec3::UnitX();
  }
  if (linear.determinant() < 0) {
    for (auto& t : part->triangles) std::swap(t[1], t[2]);
  }
}

// One primitive, appended to `mesh` with the node's transform baked in.
Status AppendPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& prim, int node,
                       const Mat4& transform, const std::string& name, const ImportLimits& limits,
                       SharedBlocks* shared, ImportedMesh* out) {
  Mesh part;
  const bool is_draco = prim.extensions.count("KHR_draco_mesh_compression") > 0;
  const std::string block_key = BlockKey(node, prim);
  const auto reuse = is_draco ? shared->end() : shared->find(block_key);
  if (is_draco) {
    SURFDEFORM_RETURN_IF_ERROR(DecodeDracoPrimitive(
        model, prim.extensions.find("KHR_draco_mesh_compression")->second, limits, &part));
  } else {
    if (AttributeOf(prim, "POSITION") < 0) return GltfError("a primitive has no POSITION");
    size_t n = 0;
    if (reuse != shared->end()) {
      n = reuse->second.count;
    } else {
      SURFDEFORM_RETURN_IF_ERROR(ReadVertexAttributes(model, prim, limits, &part));
      n = part.positions.size();
    }
    SURFDEFORM_RETURN_IF_ERROR(ReadTriangles(model, prim, n, limits, &part));
  }
  BakeTransform(transform, &part);
  Mesh& mesh = out->mesh;
  // The primitive's triangles, as a group, on vertices starting at `base`.
  auto append_triangles = [&](uint32_t base) {
    MeshGroup g;
    g.name = name;
    g.material = prim.material;
    g.part = node;
    g.first_triangle = static_cast<uint32_t>(mesh.triangles.size());
    g.triangle_count = static_cast<uint32_t>(part.triangles.size());
    for (const auto& t : part.triangles) {
      mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    if (g.triangle_count > 0) mesh.groups.push_back(g);
  };
  if (reuse != shared->end()) {  // only triangles: the vertices are there already
    append_triangles(reuse->second.base);
    return CheckLimit("triangles", mesh.triangles.size(), limits.max_triangles);
  }
  // Append, filling attributes that one side lacks.
  const size_t base = mesh.positions.size(), n = part.positions.size();
  if (!is_draco) (*shared)[block_key] = {static_cast<uint32_t>(base), static_cast<uint32_t>(n)};
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("vertices", base + n, limits.max_vertices));
  SURFDEFORM_RETURN_IF_ERROR(
      CheckLimit("triangles", mesh.triangles.size() + part.triangles.size(), limits.max_triangles));
  auto merge = [&](auto& dst, const auto& src, const auto& fill) {
    if (src.empty() && dst.empty()) return;
    dst.resize(base, fill);
    if (src.empty())
      dst.resize(base + n, fill);
    else
      dst.insert(dst.end(), src.begin(), src.end());
  };
  mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
  merge(mesh.normals, part.normals, Vec3::UnitZ().eval());
  merge(mesh.tangents, part.tangents, Vec4(1, 0, 0, 1));
  merge(mesh.uv0, part.uv0, Vec2::Zero().eval());
  merge(mesh.uv1, part.uv1, Vec2::Zero().eval());
  merge(mesh.colors, part.colors, Vec4(1, 1, 1, 1));
  append_triangles(static_cast<uint32_t>(base));
  return Status::Ok();
}

// The glTF JSON as tinygltf is to read it: read here first within the
// limits (its depth, its values; linear in its bytes), with every "extras"
// member and every extension this reader does not use left out as it is
// read, so that neither this document nor tinygltf's model ever holds them.
// The schema's rules for accessors, views and buffers are checked on it
// (gltf_schema.hpp). tinygltf 2.7.0 (built without its own Draco support,
// which would decode before our limits are checked) rejects the indices
// accessor of a KHR_draco_mesh_compression primitive, which has no buffer
// view by the extension's rules; the Draco data carries the faces, so
// `indices` is dropped from those primitives. Returns the JSON text to parse
// (unchanged when nothing was left out or dropped).
// The values (numbers, strings, arrays, objects) a glTF's JSON may hold,
// every "extras" and unused extension left out: some 20 a node, mesh or
// accessor, so that a file at the published limits has room to spare.
constexpr size_t kMaxGltfJsonValues = 4'000'000;

// The extensions this reader (and the GLB writer, for materials) uses.
bool UsedExtension(std::string_view name) {
  return name == "KHR_draco_mesh_compression" || name == "KHR_mesh_quantization" ||
         name.rfind("KHR_materials_", 0) == 0 || name == "KHR_texture_transform";
}

Result<std::string> CheckedGltfJson(std::string_view json, const ImportLimits& limits) {
  JsonLimits json_limits;
  json_limits.max_depth = limits.max_json_depth;
  json_limits.max_elements = kMaxGltfJsonValues;
  json_limits.max_string_bytes = limits.max_bytes;  // data: URIs
  json_limits.skip_member = [](std::string_view parent, std::string_view key) {
    return key == "extras" || (parent == "extensions" && !UsedExtension(key));
  };
  size_t skipped = 0;
  auto parsed = ParseBoundedJson(json, json_limits, "the glTF JSON", {}, &skipped);
  if (!parsed.ok()) {
    // Its message, in a mesh's terms: the field is the mesh, a limit keeps
    // its code and numbers, anything else is a malformed mesh.
    const Status& s = parsed.status();
    const ErrorCode code =
        s.code() == ErrorCode::kLimitExceeded ? s.code() : ErrorCode::kInvalidArgument;
    Status error(code, "glTF: " + s.message(), "mesh");
    return s.has_limit() ? error.WithLimit(s.limit(), s.actual()) : error;
  }
  nlohmann::json& doc = *parsed;
  if (!doc.is_object()) return GltfError("not a valid glTF 2.0 JSON document");
  std::string field;  // named in the message: errors in a mesh are the field "mesh"
  if (std::string problem = FirstGltfSchemaProblem(doc, &field); !problem.empty()) {
    return GltfError(problem);
  }
  bool changed = skipped > 0;
  if (doc.contains("meshes") && doc["meshes"].is_array()) {
    for (auto& mesh : doc["meshes"]) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
        continue;
      for (auto& prim : mesh["primitives"]) {
        if (prim.is_object() && prim.contains("extensions") && prim["extensions"].is_object() &&
            prim["extensions"].contains("KHR_draco_mesh_compression") && prim.contains("indices")) {
          prim.erase("indices");
          changed = true;
        }
      }
    }
  }
  if (!changed) return std::string(json);
  return doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// A GLB with its JSON chunk replaced (the BIN chunk kept as it is).
std::string RebuildGlb(std::string_view bytes, std::string_view old_json, std::string json) {
  while (json.size() % 4 != 0) json.push_back(' ');
  const size_t rest_offset = 20 + old_json.size();
  const std::string_view rest =
      rest_offset <= bytes.size() ? bytes.substr(rest_offset) : std::string_view();
  std::string out;
  const uint32_t total = static_cast<uint32_t>(12 + 8 + json.size() + rest.size());
  const uint32_t version = 2, length = static_cast<uint32_t>(json.size()), type = 0x4E4F534Au;
  out.append("glTF", 4);
  out.append(reinterpret_cast<const char*>(&version), 4);
  out.append(reinterpret_cast<const char*>(&total), 4);
  out.append(reinterpret_cast<const char*>(&length), 4);
  out.append(reinterpret_cast<const char*>(&type), 4);
  out += json;
  out.append(rest.data(), rest.size());
  return out;
}

}  // namespace

std::string_view ImageMediaType(std::string_view b) {
  if (b.size() >= 8 && b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) {
    return "image/png";
  }
  if (b.size() >= 3 && b.substr(0, 3) == std::string_view("\xff\xd8\xff", 3)) return "image/jpeg";
  return {};
}

Result<ImportedMesh> ReadGltf(std::string_view bytes, bool binary, const ImportLimits& limits) {
  ImportedMesh out;
  std::string_view json;
  SURFDEFORM_RETURN_IF_ERROR(JsonOf(bytes, binary, &json));
  SURFDEFORM_ASSIGN_OR_RETURN(auto patched, CheckedGltfJson(json, limits));
  std::string rebuilt;
  if (patched.size() != json.size() || patched != json) {
    rebuilt = binary ? RebuildGlb(bytes, json, std::move(patched)) : std::move(patched);
    bytes = rebuilt;
  }
  tinygltf::TinyGLTF loader;
  // Built without file system support; the callbacks refuse as well, should
  // that ever change.
  loader.SetFsCallbacks({&RefuseExists, &RefuseExpand, &RefuseRead, &RefuseWrite, nullptr});
  tinygltf::Model model;
  ImageSink images;
  images.model = &model;
  loader.SetImageLoader(&KeepImageBytes, &images);
  std::string err, warn;
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           static_cast<unsigned int>(bytes.size()), "")
             : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                          static_cast<unsigned int>(bytes.size()), "");
  if (!ok) {
    // tinygltf's text can quote URIs from the input: say what happened instead.
    if (err.find("external files") != std::string::npos || err.find("File") != std::string::npos ||
        err.find("file") != std::string::npos) {
      return GltfError(
          "buffers must be embedded (GLB or data: URIs); external files are never read");
    }
    return GltfError(binary ? "not a valid GLB file (truncated, or a bad chunk)"
                            : "not a valid glTF 2.0 JSON document");
  }
  // An extension the file requires and we do not implement would be misread.
  for (const std::string& ext : model.extensionsRequired) {
    if (ext != "KHR_draco_mesh_compression" && ext != "KHR_mesh_quantization" &&
        ext.rfind("KHR_materials_", 0) != 0 && ext != "KHR_texture_transform") {
      return Status(
          ErrorCode::kUnsupportedFormat,
          "glTF: the file requires the extension " + ext.substr(0, 64) + ", which is not supported",
          "mesh");
    }
  }
  for (const tinygltf::Material& m : model.materials) {
    out.materials.push_back(m.name.empty() ? "material" + std::to_string(out.materials.size())
                                           : m.name);
  }
  SURFDEFORM_ASSIGN_OR_RETURN(out.look,
                              LookOf(model, std::move(images.kept), limits, &out.warnings));
  // Every node of the default scene (or of all scenes, or every root node),
  // iteratively, each visited once (cycles in the node graph are errors).
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int s =
        model.defaultScene >= 0 && model.defaultScene < static_cast<int>(model.scenes.size())
            ? model.defaultScene
            : 0;
    roots = model.scenes[s].nodes;
  } else {
    std::vector<bool> child(model.nodes.size(), false);
    for (const auto& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && c < static_cast<int>(child.size())) child[c] = true;
    for (size_t k = 0; k < child.size(); ++k)
      if (!child[k]) roots.push_back(static_cast<int>(k));
  }
  size_t points_lines = 0, skins = 0, targets = 0;
  std::vector<std::pair<int, Mat4>> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it)
    stack.emplace_back(*it, Mat4::Identity());
  std::unordered_set<int> visited;
  SharedBlocks shared;
  while (!stack.empty()) {
    auto [index, parent] = stack.back();
    stack.pop_back();
    if (index < 0 || index >= static_cast<int>(model.nodes.size())) {
      return GltfError("node " + std::to_string(index) + " does not exist");
    }
    if (!visited.insert(index).second) {
      return GltfError("node " + std::to_string(index) +
                       " is reached twice (a cycle in the scene)");
    }
    const tinygltf::Node& node = model.nodes[index];
    const Mat4 world = parent * NodeMatrix(node);
    if (!world.allFinite())
      return GltfError("node " + std::to_string(index) + " has a non-finite transform");
    if (node.skin >= 0) ++skins;
    if (node.mesh >= 0) {
      if (node.mesh >= static_cast<int>(model.meshes.size())) {
        return GltfError("node " + std::to_string(index) + " uses a mesh that does not exist");
      }
      const tinygltf::Mesh& m = model.meshes[node.mesh];
      for (size_t p = 0; p < m.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = m.primitives[p];
        const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
        if (mode < TINYGLTF_MODE_TRIANGLES) {
          ++points_lines;
          continue;
        }
        if (!prim.targets.empty()) ++targets;
        if (prim.material >= static_cast<int>(model.materials.size())) {
          return GltfError("a primitive uses a material that does not exist");
        }
        const std::string name = m.name.empty() ? "mesh" + std::to_string(node.mesh) : m.name;
        SURFDEFORM_RETURN_IF_ERROR(
            AppendPrimitive(model, prim, index, world, name, limits, &shared, &out));
      }
    }
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
      stack.emplace_back(*c, world);
  }
  if (points_lines > 0) {
    out.warnings.push_back("ignored " + std::to_string(points_lines) + " point or line primitives");
  }
  if (skins > 0) out.warnings.push_back("ignored skins: the mesh is read in its bind pose");
  if (targets > 0) out.warnings.push_back("ignored morph targets");
  return out;
}

}  // namespace surfdeform::meshio
