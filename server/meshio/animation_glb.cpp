#include "meshio/animation_glb.hpp"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "engine/parallel.hpp"
#include "meshio/gltf_model.hpp"
#include "meshio/meshopt_views.hpp"

namespace surfdeform {
namespace {

using meshio::AddAccessor;
using meshio::AddView;
using meshio::Floats;
using meshio::ViewCodec;

struct Quantizer {
  Vec3f origin = Vec3f::Zero();
  float step = 1.0f;  // model units per integer step
  std::array<int16_t, 4> operator()(const Vec3f& p) const {
    std::array<int16_t, 4> q{};
    for (int c = 0; c < 3; ++c) {
      const float v = std::round((p[c] - origin[c]) / step);
      q[c] = static_cast<int16_t>(std::clamp(v, -16383.0f, 16383.0f));
    }
    return q;
  }
};

// Over the bounding box of every frame: integers within +-16383, so that
// the difference of two fits 16 bits.
Quantizer MakeQuantizer(const MorphAnimation& a) {
  Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::max());
  Vec3f hi = -lo;
  for (const auto& frame : a.positions) {
    for (const Vec3f& p : frame) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  Quantizer q;
  q.origin = 0.5f * (lo + hi);
  const float side = (hi - lo).maxCoeff();
  q.step = side > 0.0f ? side / 32766.0f : 1.0f;
  return q;
}

std::vector<double> MinMax(const std::vector<std::array<int16_t, 4>>& v, bool max) {
  std::vector<double> out(3, 0.0);
  for (int c = 0; c < 3; ++c) {
    int m = v.empty() ? 0 : v[0][c];
    for (const auto& q : v) m = max ? std::max<int>(m, q[c]) : std::min<int>(m, q[c]);
    out[c] = m;
  }
  return out;
}

Result<meshio::BuiltGlb> BuildModel(const MorphAnimation& a, const AnimationGlbOptions& o) {
  const Mesh& base = *a.base;
  const size_t n = base.positions.size();
  const size_t frames = a.positions.size();
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "surfdeform";
  m.buffers.resize(1);
  // Room for every view at once (the frames' dominate), so that the buffer
  // is not copied as it grows.
  const size_t per_vertex = 8 + (a.normals.empty() ? 0 : 12);
  m.buffers[0].data.reserve(frames * n * per_vertex + n * 64 + base.triangles.size() * 12 +
                            frames * (frames + 8) + 4096);
  std::vector<ViewCodec> codecs;
  auto view = [&](const void* data, size_t bytes, int target, ViewCodec codec) {
    const int v = AddView(&m, data, bytes, target);
    if (codec.stride > 0) m.bufferViews[v].byteStride = static_cast<size_t>(codec.stride);
    // Only vertex attributes have a stride in glTF; the codec's is its own.
    if (target != TINYGLTF_TARGET_ARRAY_BUFFER) m.bufferViews[v].byteStride = 0;
    codecs.resize(m.bufferViews.size());
    codecs[v] = codec;
    return v;
  };
  const ViewCodec kAttr8{ViewCodec::Mode::kAttributes, 8};
  const ViewCodec kAttr12{ViewCodec::Mode::kAttributes, 12};

  // Positions: frame 0 quantized, and each frame's integer change.
  const Quantizer quant = MakeQuantizer(a);
  std::vector<std::array<int16_t, 4>> q0(n);
  for (size_t v = 0; v < n; ++v) q0[v] = quant(a.positions[0][v]);
  std::map<std::string, int> attrs;
  attrs["POSITION"] = AddAccessor(
      &m, view(q0.data(), q0.size() * 8, TINYGLTF_TARGET_ARRAY_BUFFER, kAttr8),
      TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3, n, MinMax(q0, false), MinMax(q0, true));
  m.accessors[attrs["POSITION"]].normalized = true;
  const bool with_normals = !a.normals.empty();
  if (with_normals) {
    const std::vector<float> n0 = Floats(a.normals[0], 3);
    attrs["NORMAL"] =
        AddAccessor(&m, view(n0.data(), n0.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER, kAttr12),
                    TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
  }
  auto floats = [&](const char* name, const std::vector<float>& data, int type, int comps) {
    const ViewCodec codec{ViewCodec::Mode::kAttributes, 4 * comps};
    attrs[name] =
        AddAccessor(&m, view(data.data(), data.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER, codec),
                    TINYGLTF_COMPONENT_TYPE_FLOAT, type, n);
  };
  if (!base.uv0.empty()) floats("TEXCOORD_0", Floats(base.uv0, 2), TINYGLTF_TYPE_VEC2, 2);
  if (!base.uv1.empty()) floats("TEXCOORD_1", Floats(base.uv1, 2), TINYGLTF_TYPE_VEC2, 2);
  if (!base.colors.empty()) floats("COLOR_0", Floats(base.colors, 4), TINYGLTF_TYPE_VEC4, 4);

  // Frames 1.. : their views laid out first, in order, then filled in
  // parallel (quantized position changes, rounded normal changes, and the
  // ranges of the positions), then their accessors, in the same order as
  // the views.
  struct FrameViews {
    int positions = -1, normals = -1;
    std::vector<double> lo, hi;
  };
  std::vector<FrameViews> fv(frames);
  for (size_t k = 1; k < frames; ++k) {
    fv[k].positions = view(nullptr, n * 8, TINYGLTF_TARGET_ARRAY_BUFFER, kAttr8);
    if (with_normals) fv[k].normals = view(nullptr, n * 12, TINYGLTF_TARGET_ARRAY_BUFFER, kAttr12);
  }
  unsigned char* const bytes = m.buffers[0].data.data();
  auto at = [&](int v) { return bytes + m.bufferViews[v].byteOffset; };
  // Frames begin..end - 1 (1-based: frame 0 has no view).
  auto fill = [&](int, int begin, int end) {
    if (n == 0) return;  // no data to copy (memcpy from null is undefined)
    std::vector<std::array<int16_t, 4>> qk(n);
    std::vector<float> dn(with_normals ? 3 * n : 0);
    for (int k = begin + 1; k < end + 1; ++k) {
      for (size_t v = 0; v < n; ++v) {
        const auto q = quant(a.positions[k][v]);
        for (int c = 0; c < 3; ++c) qk[v][c] = static_cast<int16_t>(q[c] - q0[v][c]);
        qk[v][3] = 0;
      }
      std::memcpy(at(fv[k].positions), qk.data(), n * 8);
      fv[k].lo = MinMax(qk, false);
      fv[k].hi = MinMax(qk, true);
      if (!with_normals) continue;
      for (size_t v = 0; v < n; ++v) {
        for (int c = 0; c < 3; ++c) {
          const float d = a.normals[k][v][c] - a.normals[0][v][c];
          dn[3 * v + c] = std::round(d * 4096.0f) / 4096.0f;
        }
      }
      std::memcpy(at(fv[k].normals), dn.data(), n * 12);
    }
  };
  ParallelChunks(static_cast<int>(frames) - 1, ResolveThreads(o.threads), fill);
  std::vector<std::map<std::string, int>> targets(frames);
  for (size_t k = 0; k < frames; ++k) {
    if (k == 0) {  // no change: zeros, with no buffer view
      targets[0]["POSITION"] = AddAccessor(&m, -1, TINYGLTF_COMPONENT_TYPE_SHORT,
                                           TINYGLTF_TYPE_VEC3, n, {0, 0, 0}, {0, 0, 0});
      m.accessors[targets[0]["POSITION"]].normalized = true;
      if (with_normals) {
        targets[0]["NORMAL"] =
            AddAccessor(&m, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
      }
      continue;
    }
    targets[k]["POSITION"] = AddAccessor(&m, fv[k].positions, TINYGLTF_COMPONENT_TYPE_SHORT,
                                         TINYGLTF_TYPE_VEC3, n, fv[k].lo, fv[k].hi);
    m.accessors[targets[k]["POSITION"]].normalized = true;
    if (with_normals) {
      targets[k]["NORMAL"] =
          AddAccessor(&m, fv[k].normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
    }
  }

  meshio::AddMaterials(&m, o.look);
  std::vector<MeshGroup> groups = base.groups;
  if (groups.empty())
    groups.push_back({"mesh", -1, 0, static_cast<uint32_t>(base.triangles.size())});
  tinygltf::Mesh gm;
  gm.name = groups.front().name.empty() ? "animation" : groups.front().name;
  gm.weights.assign(frames, 0.0);
  tinygltf::Value::Array names;
  for (size_t k = 0; k < frames; ++k) names.emplace_back("frame " + std::to_string(k));
  tinygltf::Value::Object extras;
  extras["targetNames"] = tinygltf::Value(names);
  gm.extras = tinygltf::Value(extras);
  for (const MeshGroup& g : groups) {
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material =
        g.material >= 0 && g.material < static_cast<int>(m.materials.size()) ? g.material : -1;
    prim.attributes = attrs;
    prim.targets = targets;
    std::vector<uint32_t> idx;
    idx.reserve(3 * size_t{g.triangle_count});
    for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t)
      for (uint32_t v : base.triangles[t]) idx.push_back(v);
    SURFDEFORM_RETURN_IF_ERROR(meshio::AsTheCodecDecodes(&idx));
    const int iv = view(idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER,
                        {ViewCodec::Mode::kTriangles, 4});
    prim.indices =
        AddAccessor(&m, iv, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, idx.size());
    gm.primitives.push_back(prim);
  }
  m.meshes.push_back(gm);

  // The weights' animation: one-hot at each frame's time, LINEAR between.
  std::vector<float> times(frames);
  for (size_t k = 0; k < frames; ++k) times[k] = static_cast<float>(static_cast<double>(k) / a.fps);
  std::vector<uint8_t> weights(frames * frames, 0);
  for (size_t k = 0; k < frames; ++k) weights[k * frames + k] = 255;
  weights.resize((weights.size() + 3) / 4 * 4, 0);  // whole 4-byte elements for the codec
  const ViewCodec kAnim{ViewCodec::Mode::kAttributes, 4};
  const int input =
      AddAccessor(&m, view(times.data(), times.size() * 4, 0, kAnim), TINYGLTF_COMPONENT_TYPE_FLOAT,
                  TINYGLTF_TYPE_SCALAR, frames, {times.front()}, {times.back()});
  const int output =
      AddAccessor(&m, view(weights.data(), weights.size(), 0, kAnim),
                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_SCALAR, frames * frames);
  m.accessors[output].normalized = true;
  tinygltf::Animation anim;
  anim.name = "surface";
  tinygltf::AnimationSampler sampler;
  sampler.input = input;
  sampler.output = output;
  sampler.interpolation = "LINEAR";
  anim.samplers.push_back(sampler);
  tinygltf::AnimationChannel channel;
  channel.sampler = 0;
  channel.target_node = 0;
  channel.target_path = "weights";
  anim.channels.push_back(channel);
  m.animations.push_back(anim);

  meshio::AddQuantizedNode(&m, gm.name, {quant.origin.x(), quant.origin.y(), quant.origin.z()},
                           static_cast<double>(quant.step) * 32767.0);
  return meshio::Finish(&m, std::move(codecs));
}

}  // namespace

Result<std::string> WriteAnimationGlb(const MorphAnimation& a, const AnimationGlbOptions& o) {
  if (a.base == nullptr || a.positions.empty()) {
    return InvalidArgument("an animation needs a mesh and at least one frame", "frames");
  }
  const size_t n = a.base->positions.size();
  for (size_t k = 0; k < a.positions.size(); ++k) {
    const bool normals_ok =
        a.normals.empty() || (a.normals.size() == a.positions.size() && a.normals[k].size() == n);
    if (a.positions[k].size() != n || !normals_ok) {
      return InvalidArgument("frame " + std::to_string(k) + " does not match the mesh", "frames");
    }
    for (const Vec3f& p : a.positions[k]) {
      if (!p.allFinite()) {
        return InvalidArgument("frame " + std::to_string(k) + " has a position that is not finite",
                               "frames");
      }
    }
  }
  if (!(a.fps > 0.0)) return InvalidArgument("must be positive", "fps");
  if (std::string problem = CheckMesh(*a.base); !problem.empty()) {
    return InvalidArgument("malformed mesh: " + problem, "mesh");
  }
  SURFDEFORM_ASSIGN_OR_RETURN(meshio::BuiltGlb built, BuildModel(a, o));
  if (o.compression == AnimationCompression::kNone) {
    return meshio::Glb(built.doc, built.bin_view());
  }
  return meshio::Compress(std::move(built), ResolveThreads(o.threads));
}

}  // namespace surfdeform
