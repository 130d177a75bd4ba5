#include "meshio/draco_io.hpp"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "base/fault_points.hpp"
#include "meshio/importers.hpp"

namespace surfdeform::meshio {
namespace {

// Reads a base-128 varint as Draco writes it.
bool ReadVarint(std::string_view* s, uint64_t* out) {
  uint64_t v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (s->empty()) return false;
    const uint8_t b = static_cast<uint8_t>(s->front());
    s->remove_prefix(1);
    v |= static_cast<uint64_t>(b & 0x7f) << shift;
    if (!(b & 0x80)) {
      *out = v;
      return true;
    }
  }
  return false;
}

// The face and point counts a Draco 2.2 mesh claims, read from its header
// before the decoder allocates anything (a 61-byte file can otherwise make
// Draco 1.5.5 reserve gigabytes).
Status PeekCounts(std::string_view bytes, uint64_t* faces, uint64_t* points) {
  auto bad = [](const std::string& what) { return InvalidArgument("Draco: " + what, "mesh"); };
  if (bytes.size() < 11) return bad("the header is truncated");
  const uint8_t major = static_cast<uint8_t>(bytes[5]), minor = static_cast<uint8_t>(bytes[6]);
  const uint8_t type = static_cast<uint8_t>(bytes[7]), method = static_cast<uint8_t>(bytes[8]);
  uint16_t flags;
  std::memcpy(&flags, bytes.data() + 9, 2);
  if (major != 2 || minor != 2) {
    return Status(ErrorCode::kUnsupportedFormat,
                  "Draco bitstream version " + std::to_string(major) + "." + std::to_string(minor) +
                      " is not supported (2.2 is)",
                  "mesh");
  }
  if (type != 1) return bad("the file holds a point cloud, not a triangle mesh");
  if (flags & 0x8000) return bad("Draco metadata is not supported");
  std::string_view rest = bytes.substr(11);
  uint64_t skip;
  if (method == 0) {  // sequential: num_faces, num_points
    if (!ReadVarint(&rest, faces) || !ReadVarint(&rest, points)) return bad("truncated header");
    return Status::Ok();
  }
  if (method == 1) {  // edgebreaker: traversal type, new vertices, vertices, faces
    if (rest.empty()) return bad("truncated header");
    rest.remove_prefix(1);
    if (!ReadVarint(&rest, &skip) || !ReadVarint(&rest, points) || !ReadVarint(&rest, faces)) {
      return bad("truncated header");
    }
    return Status::Ok();
  }
  return bad("unknown encoding method " + std::to_string(method));
}

// Adds a float attribute of `components` per vertex, value(k, out) writing
// vertex k's; the values go into Draco's buffer in one write.
template <typename Value>
int AddAttribute(draco::Mesh* dm, draco::GeometryAttribute::Type type, int components, size_t n,
                 const Value& value) {
  draco::GeometryAttribute ga;
  ga.Init(type, nullptr, static_cast<uint8_t>(components), draco::DT_FLOAT32, false,
          sizeof(float) * components, 0);
  const int id = dm->AddAttribute(ga, true, static_cast<uint32_t>(n));
  std::vector<float> values(n * components);
  for (size_t k = 0; k < n; ++k) value(k, values.data() + k * components);
  dm->attribute(id)->buffer()->Write(0, values.data(), values.size() * sizeof(float));
  return id;
}

}  // namespace

namespace {

// The box Draco's quantization takes over `values` (as floats, which Draco
// reads): per-component minimum, and the largest extent (1 for none).
template <typename V, size_t N>
void GridOf(const std::vector<const std::vector<V>*>& sets, std::array<float, N>* origin,
            float* range) {
  std::array<float, N> lo, hi;
  lo.fill(std::numeric_limits<float>::max());
  hi.fill(std::numeric_limits<float>::lowest());
  bool any = false;
  for (const std::vector<V>* values : sets) {
    for (const V& v : *values) {
      any = true;
      for (size_t c = 0; c < N; ++c) {
        const float x = static_cast<float>(v[static_cast<Eigen::Index>(c)]);
        lo[c] = std::min(lo[c], x);
        hi[c] = std::max(hi[c], x);
      }
    }
  }
  if (!any) return;
  float extent = 0.0f;
  for (size_t c = 0; c < N; ++c) extent = std::max(extent, hi[c] - lo[c]);
  *origin = lo;
  *range = extent > 0.0f ? extent : 1.0f;
}

}  // namespace

DracoGrid DracoGridOf(const Mesh& mesh) {
  DracoGrid g;
  GridOf<Vec3, 3>({&mesh.positions}, &g.position_origin, &g.position_range);
  GridOf<Vec2, 2>({&mesh.uv0, &mesh.uv1}, &g.uv_origin, &g.uv_range);
  GridOf<Vec4, 4>({&mesh.colors}, &g.color_origin, &g.color_range);
  return g;
}

Result<std::string> EncodeDraco(const Mesh& mesh, const DracoOptions& o,
                                int ids[kGltfDracoAttributes], const DracoGrid* grid) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateDracoOptions(o));
  const size_t n = mesh.positions.size();
  draco::Mesh dm;
  dm.set_num_points(static_cast<uint32_t>(n));
  dm.SetNumFaces(mesh.triangles.size());
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    dm.SetFace(draco::FaceIndex(static_cast<uint32_t>(f)),
               {draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
  }
  int local[kGltfDracoAttributes] = {-1, -1, -1, -1, -1, -1, -1};
  using GA = draco::GeometryAttribute;
  local[0] = AddAttribute(&dm, GA::POSITION, 3, n, [&](size_t k, float* f) {
    for (int c = 0; c < 3; ++c) f[c] = static_cast<float>(mesh.positions[k][c]);
  });
  if (!mesh.normals.empty()) {
    local[1] = AddAttribute(&dm, GA::NORMAL, 3, n, [&](size_t k, float* f) {
      for (int c = 0; c < 3; ++c) f[c] = static_cast<float>(mesh.normals[k][c]);
    });
  }
  const std::vector<Vec2>* uvs[2] = {&mesh.uv0, &mesh.uv1};
  for (int u = 0; u < 2; ++u) {
    if (uvs[u]->empty()) continue;
    local[2 + u] = AddAttribute(&dm, GA::TEX_COORD, 2, n, [&](size_t k, float* f) {
      f[0] = static_cast<float>((*uvs[u])[k].x());
      f[1] = static_cast<float>((*uvs[u])[k].y());
    });
  }
  if (!mesh.colors.empty()) {
    local[4] = AddAttribute(&dm, GA::COLOR, 4, n, [&](size_t k, float* f) {
      for (int c = 0; c < 4; ++c) f[c] = static_cast<float>(mesh.colors[k][c]);
    });
  }
  if (!mesh.tangents.empty()) {
    local[5] = AddAttribute(&dm, GA::GENERIC, 4, n, [&](size_t k, float* f) {
      for (int c = 0; c < 4; ++c) f[c] = static_cast<float>(mesh.tangents[k][c]);
    });
  }
  if (!mesh.distortion.empty() && ids != nullptr) {
    local[6] = AddAttribute(&dm, GA::GENERIC, 2, n, [&](size_t k, float* f) {
      f[0] = static_cast<float>(mesh.distortion[k].x());
      f[1] = static_cast<float>(mesh.distortion[k].y());
    });
  }
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(GA::POSITION, o.position_bits);
  encoder.SetAttributeQuantization(GA::NORMAL, o.normal_bits);
  encoder.SetAttributeQuantization(GA::TEX_COORD, o.uv_bits);
  encoder.SetAttributeQuantization(GA::COLOR, o.color_bits);
  if (grid != nullptr) {
    encoder.SetAttributeExplicitQuantization(GA::POSITION, o.position_bits, 3,
                                             grid->position_origin.data(), grid->position_range);
    encoder.SetAttributeExplicitQuantization(GA::TEX_COORD, o.uv_bits, 2, grid->uv_origin.data(),
                                             grid->uv_range);
    encoder.SetAttributeExplicitQuantization(GA::COLOR, o.color_bits, 4, grid->color_origin.data(),
                                             grid->color_range);
  }
  encoder.SetSpeedOptions(o.speed, o.speed);
  encoder.SetEncodingMethod(o.sequential ? draco::MESH_SEQUENTIAL_ENCODING
                                         : draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer buffer;
  auto encode = [&] {
    return faults::Armed(faults::Fault::kDracoEncodeFails)
               ? draco::Status(draco::Status::DRACO_ERROR, "injected fault")
               : encoder.EncodeMeshToBuffer(dm, &buffer);
  };
  draco::Status st = encode();
  if (!st.ok() && !o.sequential) {
    // Edgebreaker refuses some valid connectivity (every triangle
    // degenerate, two of its corners on one vertex); the sequential coding
    // takes any, and every Draco decoder reads both.
    encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
    buffer.Clear();
    st = encode();
  }
  if (!st.ok()) {
    return Status(ErrorCode::kInternal, std::string("Draco encoding failed: ") + st.error_msg());
  }
  if (ids != nullptr) {
    for (int k = 0; k < kGltfDracoAttributes; ++k) {
      ids[k] = local[k] < 0 ? -1 : dm.attribute(local[k])->unique_id();
    }
  }
  return std::string(buffer.data(), buffer.size());
}

Status DecodeDraco(std::string_view bytes, const ImportLimits& limits, Mesh* mesh,
                   const int gltf_ids[6]) {
  if (bytes.substr(0, 5) != "DRACO") return InvalidArgument("Draco: no DRACO magic", "mesh");
  uint64_t faces = 0, points = 0;
  SURFDEFORM_RETURN_IF_ERROR(PeekCounts(bytes, &faces, &points));
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("triangles", faces, limits.max_triangles));
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("vertices", points, limits.max_vertices));
  // Counts the bytes cannot hold are refused before Draco allocates for them
  // (its decoder sizes buffers from the header; docs/RELIABILITY.md, item
  // 7). Draco is dense: a 500 x 500 grid at 1-bit positions, edgebreaker at
  // level 7, is 678 bytes, 369 vertices and 735 triangles a byte. The bound
  // is ten times that.
  constexpr uint64_t kMaxVerticesPerByte = 4096, kMaxTrianglesPerByte = 8192;
  if (points > kMaxVerticesPerByte * bytes.size() || faces > kMaxTrianglesPerByte * bytes.size()) {
    return Status::LimitExceeded("Draco: the header claims " + std::to_string(points) +
                                     " vertices and " + std::to_string(faces) +
                                     " triangles, more than " + std::to_string(bytes.size()) +
                                     " bytes can hold",
                                 "mesh", static_cast<double>(kMaxVerticesPerByte * bytes.size()),
                                 static_cast<double>(points));
  }
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) {
    return InvalidArgument(std::string("Draco: cannot decode: ") + decoded.status().error_msg(),
                           "mesh");
  }
  const std::unique_ptr<draco::Mesh> dm = std::move(decoded).value();
  const uint32_t n = dm->num_points();
  SURFDEFORM_RETURN_IF_ERROR(CheckLimit("vertices", n, limits.max_vertices));
  using GA = draco::GeometryAttribute;
  auto find = [&](int slot, GA::Type type, int nth) -> const draco::PointAttribute* {
    if (gltf_ids != nullptr) {
      return gltf_ids[slot] < 0 ? nullptr
                                : dm->GetAttributeByUniqueId(static_cast<uint32_t>(gltf_ids[slot]));
    }
    const int id = dm->GetNamedAttributeId(type, nth);
    return id < 0 ? nullptr : dm->attribute(id);
  };
  const draco::PointAttribute* pos = find(0, GA::POSITION, 0);
  if (pos == nullptr || pos->num_components() < 3) {
    return InvalidArgument("Draco: the mesh has no 3D positions", "mesh");
  }
  auto read = [&](const draco::PointAttribute* att, int comps, auto&& store) -> Status {
    if (att == nullptr) return Status::Ok();
    if (att->num_components() < comps) {
      return InvalidArgument("Draco: an attribute has too few components", "mesh");
    }
    float buf[4] = {0, 0, 0, 1};
    for (uint32_t k = 0; k < n; ++k) {
      if (!att->ConvertValue<float>(att->mapped_index(draco::PointIndex(k)),
                                    static_cast<int8_t>(comps), buf)) {
        return InvalidArgument("Draco: cannot read an attribute value", "mesh");
      }
      store(k, buf);
    }
    return Status::Ok();
  };
  mesh->positions.resize(n);
  SURFDEFORM_RETURN_IF_ERROR(read(
      pos, 3, [&](uint32_t k, const float* f) { mesh->positions[k] = Vec3(f[0], f[1], f[2]); }));
  if (const auto* att = find(1, GA::NORMAL, 0)) {
    mesh->normals.resize(n);
    SURFDEFORM_RETURN_IF_ERROR(read(att, 3, [&](uint32_t k, const float* f) {
      const Vec3 v(f[0], f[1], f[2]);
      mesh->normals[k] = v.norm() > 0 ? Vec3(v.normalized()) : Vec3::UnitZ();
    }));
  }
  std::vector<Vec2>* uvs[2] = {&mesh->uv0, &mesh->uv1};
  for (int u = 0; u < 2; ++u) {
    if (const auto* att = find(2 + u, GA::TEX_COORD, u)) {
      uvs[u]->resize(n);
      SURFDEFORM_RETURN_IF_ERROR(
          read(att, 2, [&](uint32_t k, const float* f) { (*uvs[u])[k] = Vec2(f[0], f[1]); }));
    }
  }
  if (const auto* att = find(4, GA::COLOR, 0)) {
    mesh->colors.resize(n);
    const int comps = std::min<int>(4, att->num_components());
    SURFDEFORM_RETURN_IF_ERROR(read(att, comps, [&](uint32_t k, const float* f) {
      mesh->colors[k] = Vec4(f[0], f[1], f[2], comps == 4 ? f[3] : 1.0f);
    }));
    // Integer colours are normalised by ConvertValue only when flagged: scale.
    if (att->data_type() == draco::DT_UINT8 && !att->normalized()) {
      for (Vec4& c : mesh->colors) c /= 255.0;
    }
  }
  if (const auto* att = find(5, GA::GENERIC, 0); att != nullptr && att->num_components() == 4) {
    mesh->tangents.resize(n);
    SURFDEFORM_RETURN_IF_ERROR(read(att, 4, [&](uint32_t k, const float* f) {
      mesh->tangents[k] = Vec4(f[0], f[1], f[2], f[3] < 0 ? -1.0 : 1.0);
    }));
  }
  mesh->triangles.resize(dm->num_faces());
  for (uint32_t f = 0; f < dm->num_faces(); ++f) {
    const auto& face = dm->face(draco::FaceIndex(f));
    for (int c = 0; c < 3; ++c) {
      if (face[c].value() >= n)
        return InvalidArgument("Draco: a face index is out of range", "mesh");
      mesh->triangles[f][c] = face[c].value();
    }
  }
  return Status::Ok();
}

Result<ImportedMesh> ReadDraco(std::string_view bytes, const ImportLimits& limits) {
  ImportedMesh out;
  SURFDEFORM_RETURN_IF_ERROR(DecodeDraco(bytes, limits, &out.mesh));
  return out;
}

}  // namespace surfdeform::meshio
