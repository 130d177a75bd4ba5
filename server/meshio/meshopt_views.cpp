#include "meshio/meshopt_views.hpp"

#include <meshoptimizer.h>

#include <cstring>
#include <sstream>

#include "engine/common/parallel.hpp"

namespace surfdeform::meshio {
namespace {

using nlohmann::json;

void AppendU32(std::string* s, uint32_t v) { s->append(reinterpret_cast<const char*>(&v), 4); }

uint32_t ReadU32(const std::string& s, size_t at) {
  uint32_t v = 0;
  std::memcpy(&v, s.data() + at, 4);
  return v;
}

}  // namespace

void AddQuantizedNode(tinygltf::Model* m, const std::string& name,
                      const std::array<double, 3>& origin, double scale) {
  tinygltf::Node node;
  node.mesh = 0;
  node.name = name;
  node.translation = {origin[0], origin[1], origin[2]};
  node.scale = {scale, scale, scale};
  m->nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  m->scenes.push_back(scene);
  m->defaultScene = 0;
  m->extensionsUsed.push_back("KHR_mesh_quantization");
  m->extensionsRequired.push_back("KHR_mesh_quantization");
}

Result<BuiltGlb> Finish(tinygltf::Model* m, std::vector<ViewCodec> codecs) {
  m->buffers[0].data.resize((m->buffers[0].data.size() + 3) / 4 * 4, 0);
  // tinygltf writes the document; the binary buffer (tens of MB for a long
  // animation) stays out of its stream, which would copy it three times.
  BuiltGlb built;
  built.bin = std::move(m->buffers[0].data);
  m->buffers[0].data.clear();
  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  if (!writer.WriteGltfSceneToStream(m, out, false, true)) {
    return Status(ErrorCode::kInternal, "GLB writing failed");
  }
  const std::string glb = out.str();
  if (glb.size() < 20) return Status(ErrorCode::kInternal, "GLB writing failed");
  built.doc = json::parse(glb.substr(20, ReadU32(glb, 12)), nullptr, false);
  if (built.doc.is_discarded()) return Status(ErrorCode::kInternal, "GLB writing failed");
  built.doc["buffers"] = json::array({{{"byteLength", built.bin.size()}}});
  codecs.resize(m->bufferViews.size());
  built.codecs = std::move(codecs);
  return built;
}

std::string Glb(const json& doc, std::string_view bin) {
  std::string text = doc.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  std::string out;
  AppendU32(&out, 0x46546C67);  // "glTF"
  AppendU32(&out, 2);
  AppendU32(&out, static_cast<uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  AppendU32(&out, static_cast<uint32_t>(text.size()));
  AppendU32(&out, 0x4E4F534A);  // "JSON"
  out += text;
  AppendU32(&out, static_cast<uint32_t>(bin.size()));
  AppendU32(&out, 0x004E4942);  // "BIN\0"
  out += bin;
  return out;
}

// The uncompressed GLB with its vertex, index and animation views compressed
// (EXT_meshopt_compression): their data move to buffer 0 compressed, and the
// views themselves point into buffer 1, a fallback with no data and the
// uncompressed layout.
Result<std::string> Compress(BuiltGlb built, int threads) {
  json& doc = built.doc;
  const std::string_view bin = built.bin_view();
  json& views = doc["bufferViews"];
  const int n = static_cast<int>(views.size());
  std::vector<std::string_view> data(n);
  for (int v = 0; v < n; ++v) {
    data[v] =
        bin.substr(views[v].value("byteOffset", size_t{0}), views[v]["byteLength"].get<size_t>());
  }
  static const ViewCodec kUncompressed;
  auto codec_of = [&built](int v) -> const ViewCodec& {
    return static_cast<size_t>(v) < built.codecs.size() ? built.codecs[v] : kUncompressed;
  };
  // The views compressed independently (in parallel), then laid out in order.
  std::vector<std::vector<unsigned char>> encoded(n);
  std::vector<size_t> counts(n, 0);
  ParallelChunks(n, threads, [&](int, int begin, int end) {
    for (int v = begin; v < end; ++v) {
      const ViewCodec& codec = codec_of(v);
      const size_t length = data[v].size();
      std::vector<unsigned char>& out = encoded[v];
      if (codec.mode == ViewCodec::Mode::kTriangles) {
        const size_t count = counts[v] = length / 4;
        std::vector<unsigned int> idx(count);
        std::memcpy(idx.data(), data[v].data(), length);
        out.resize(meshopt_encodeIndexBufferBound(count, count));
        out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), idx.data(), count));
      } else if (codec.mode == ViewCodec::Mode::kAttributes) {
        const size_t count = counts[v] = length / static_cast<size_t>(codec.stride);
        out.resize(meshopt_encodeVertexBufferBound(count, codec.stride));
        const void* source = codec.filtered.empty() ? static_cast<const void*>(data[v].data())
                                                    : codec.filtered.data();
        out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), source, count, codec.stride));
      }
    }
  });
  std::string packed;
  for (int v = 0; v < n; ++v) {
    json& view = views[v];
    while (packed.size() % 4 != 0) packed.push_back('\0');
    const ViewCodec& codec = codec_of(v);
    if (codec.mode == ViewCodec::Mode::kNone) {  // images: as they are, in buffer 0
      view["byteOffset"] = packed.size();
      packed.append(data[v]);
      continue;
    }
    if (encoded[v].empty()) return Status(ErrorCode::kInternal, "meshopt compression failed");
    const char* mode = codec.mode == ViewCodec::Mode::kTriangles ? "TRIANGLES" : "ATTRIBUTES";
    view["extensions"]["EXT_meshopt_compression"] = {{"buffer", 0},
                                                     {"byteOffset", packed.size()},
                                                     {"byteLength", encoded[v].size()},
                                                     {"byteStride", codec.stride},
                                                     {"count", counts[v]},
                                                     {"mode", mode}};
    if (codec.filter != nullptr) {
      view["extensions"]["EXT_meshopt_compression"]["filter"] = codec.filter;
    }
    view["buffer"] = 1;
    packed.append(reinterpret_cast<const char*>(encoded[v].data()), encoded[v].size());
  }
  while (packed.size() % 4 != 0) packed.push_back('\0');
  doc["buffers"] =
      json::array({{{"byteLength", packed.size()}},
                   {{"byteLength", bin.size()},
                    {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}});
  doc["extensionsUsed"].push_back("EXT_meshopt_compression");
  doc["extensionsRequired"].push_back("EXT_meshopt_compression");
  return Glb(doc, packed);
}

Status AsTheCodecDecodes(std::vector<uint32_t>* idx) {
  if (idx->empty()) return Status::Ok();
  std::vector<unsigned char> encoded(meshopt_encodeIndexBufferBound(idx->size(), idx->size()));
  const size_t size =
      meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), idx->data(), idx->size());
  if (size == 0 ||
      meshopt_decodeIndexBuffer(idx->data(), idx->size(), 4, encoded.data(), size) != 0) {
    return Status(ErrorCode::kInternal, "meshopt index coding failed");
  }
  return Status::Ok();
}

}  // namespace surfdeform::meshio
