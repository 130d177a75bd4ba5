#include "meshio/animation_glb.hpp"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "engine/common/parallel.hpp"
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

// The animation's glTF model, a part at a time, in the order its buffer
// views are laid out: the base attributes, the frames' morph targets, the
// primitives' indices, the weights' animation.
class ModelBuilder {
 public:
  ModelBuilder(const MorphAnimation& a, const AnimationGlbOptions& o)
      : a_(a),
        o_(o),
        base_(*a.base),
        n_(base_.positions.size()),
        frames_(a.positions.size()),
        with_normals_(!a.normals.empty()),
        quant_(MakeQuantizer(a)) {
    m_.asset.version = "2.0";
    m_.asset.generator = "surfdeform";
    m_.buffers.resize(1);
    // Room for every view at once (the frames' dominate), so that the buffer
    // is not copied as it grows.
    const size_t per_vertex = 8 + (with_normals_ ? 12 : 0);
    m_.buffers[0].data.reserve(frames_ * n_ * per_vertex + n_ * 64 + base_.triangles.size() * 12 +
                               frames_ * (frames_ + 8) + 4096);
  }

  Result<meshio::BuiltGlb> Build() && {
    BaseAttributes();
    FrameTargets();
    meshio::AddMaterials(&m_, o_.look);
    SURFDEFORM_ASSIGN_OR_RETURN(const std::string name, Primitives());
    WeightsAnimation();
    meshio::AddQuantizedNode(&m_, name, {quant_.origin.x(), quant_.origin.y(), quant_.origin.z()},
                             static_cast<double>(quant_.step) * 32767.0);
    return meshio::Finish(&m_, std::move(codecs_));
  }

 private:
  const ViewCodec kAttr8{ViewCodec::Mode::kAttributes, 8};
  const ViewCodec kAttr12{ViewCodec::Mode::kAttributes, 12};

  int View(const void* data, size_t bytes, int target, ViewCodec codec) {
    const int v = AddView(&m_, data, bytes, target);
    if (codec.stride > 0) m_.bufferViews[v].byteStride = static_cast<size_t>(codec.stride);
    // Only vertex attributes have a stride in glTF; the codec's is its own.
    if (target != TINYGLTF_TARGET_ARRAY_BUFFER) m_.bufferViews[v].byteStride = 0;
    codecs_.resize(m_.bufferViews.size());
    codecs_[v] = codec;
    return v;
  }

  // Positions: frame 0 quantized; normals, texture coordinates and colours
  // as floats.
  void BaseAttributes() {
    q0_.resize(n_);
    for (size_t v = 0; v < n_; ++v) q0_[v] = quant_(a_.positions[0][v]);
    attrs_["POSITION"] =
        AddAccessor(&m_, View(q0_.data(), q0_.size() * 8, TINYGLTF_TARGET_ARRAY_BUFFER, kAttr8),
                    TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3, n_, MinMax(q0_, false),
                    MinMax(q0_, true));
    m_.accessors[attrs_["POSITION"]].normalized = true;
    if (with_normals_) {
      const std::vector<float> n0 = Floats(a_.normals[0], 3);
      attrs_["NORMAL"] =
          AddAccessor(&m_, View(n0.data(), n0.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER, kAttr12),
                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n_);
    }
    auto floats = [&](const char* name, const std::vector<float>& data, int type, int comps) {
      const ViewCodec codec{ViewCodec::Mode::kAttributes, 4 * comps};
      attrs_[name] =
          AddAccessor(&m_, View(data.data(), data.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER, codec),
                      TINYGLTF_COMPONENT_TYPE_FLOAT, type, n_);
    };
    if (!base_.uv0.empty()) floats("TEXCOORD_0", Floats(base_.uv0, 2), TINYGLTF_TYPE_VEC2, 2);
    if (!base_.uv1.empty()) floats("TEXCOORD_1", Floats(base_.uv1, 2), TINYGLTF_TYPE_VEC2, 2);
    if (!base_.colors.empty()) floats("COLOR_0", Floats(base_.colors, 4), TINYGLTF_TYPE_VEC4, 4);
  }

  // Frames 1.. : their views laid out first, in order, then filled in
  // parallel (quantized position changes, rounded normal changes, and the
  // ranges of the positions), then their accessors, in the same order as
  // the views. Frame 0 changes nothing: zeros, with no buffer view.
  void FrameTargets() {
    std::vector<FrameViews> fv(frames_);
    for (size_t k = 1; k < frames_; ++k) {
      fv[k].positions = View(nullptr, n_ * 8, TINYGLTF_TARGET_ARRAY_BUFFER, kAttr8);
      if (with_normals_) {
        fv[k].normals = View(nullptr, n_ * 12, TINYGLTF_TARGET_ARRAY_BUFFER, kAttr12);
      }
    }
    // Frames begin..end - 1 (1-based: frame 0 has no view).
    ParallelChunks(static_cast<int>(frames_) - 1, ResolveThreads(o_.threads),
                   [&](int, int begin, int end) { FillFrames(begin + 1, end + 1, &fv); });
    targets_.resize(frames_);
    for (size_t k = 0; k < frames_; ++k) {
      const int positions = k == 0 ? -1 : fv[k].positions;
      const std::vector<double> lo = k == 0 ? std::vector<double>{0, 0, 0} : fv[k].lo;
      const std::vector<double> hi = k == 0 ? std::vector<double>{0, 0, 0} : fv[k].hi;
      targets_[k]["POSITION"] = AddAccessor(&m_, positions, TINYGLTF_COMPONENT_TYPE_SHORT,
                                            TINYGLTF_TYPE_VEC3, n_, lo, hi);
      m_.accessors[targets_[k]["POSITION"]].normalized = true;
      if (with_normals_) {
        targets_[k]["NORMAL"] = AddAccessor(&m_, k == 0 ? -1 : fv[k].normals,
                                            TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n_);
      }
    }
  }

  struct FrameViews {
    int positions = -1, normals = -1;
    std::vector<double> lo, hi;
  };

  void FillFrames(int first, int end, std::vector<FrameViews>* fv) {
    if (n_ == 0) return;  // no data to copy (memcpy from null is undefined)
    unsigned char* const bytes = m_.buffers[0].data.data();
    auto at = [&](int v) { return bytes + m_.bufferViews[v].byteOffset; };
    std::vector<std::array<int16_t, 4>> qk(n_);
    std::vector<float> dn(with_normals_ ? 3 * n_ : 0);
    for (int k = first; k < end; ++k) {
      FrameViews& f = (*fv)[k];
      for (size_t v = 0; v < n_; ++v) {
        const auto q = quant_(a_.positions[k][v]);
        for (int c = 0; c < 3; ++c) qk[v][c] = static_cast<int16_t>(q[c] - q0_[v][c]);
        qk[v][3] = 0;
      }
      std::memcpy(at(f.positions), qk.data(), n_ * 8);
      f.lo = MinMax(qk, false);
      f.hi = MinMax(qk, true);
      if (!with_normals_) continue;
      for (size_t v = 0; v < n_; ++v) {
        for (int c = 0; c < 3; ++c) {
          const float d = a_.normals[k][v][c] - a_.normals[0][v][c];
          dn[3 * v + c] = std::round(d * 4096.0f) / 4096.0f;
        }
      }
      std::memcpy(at(f.normals), dn.data(), n_ * 12);
    }
  }

  // One primitive per group (its material), every one with the base
  // attributes and the frames' targets; the mesh's name.
  Result<std::string> Primitives() {
    std::vector<MeshGroup> groups = base_.groups;
    if (groups.empty()) {
      groups.push_back({"mesh", -1, 0, static_cast<uint32_t>(base_.triangles.size())});
    }
    tinygltf::Mesh gm;
    gm.name = groups.front().name.empty() ? "animation" : groups.front().name;
    gm.weights.assign(frames_, 0.0);
    tinygltf::Value::Array names;
    for (size_t k = 0; k < frames_; ++k) names.emplace_back("frame " + std::to_string(k));
    tinygltf::Value::Object extras;
    extras["targetNames"] = tinygltf::Value(names);
    gm.extras = tinygltf::Value(extras);
    for (const MeshGroup& g : groups) {
      tinygltf::Primitive prim;
      prim.mode = TINYGLTF_MODE_TRIANGLES;
      prim.material =
          g.material >= 0 && g.material < static_cast<int>(m_.materials.size()) ? g.material : -1;
      prim.attributes = attrs_;
      prim.targets = targets_;
      std::vector<uint32_t> idx;
      idx.reserve(3 * size_t{g.triangle_count});
      for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t)
        for (uint32_t v : base_.triangles[t]) idx.push_back(v);
      SURFDEFORM_RETURN_IF_ERROR(meshio::AsTheCodecDecodes(&idx));
      const int iv = View(idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER,
                          {ViewCodec::Mode::kTriangles, 4});
      prim.indices = AddAccessor(&m_, iv, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                 TINYGLTF_TYPE_SCALAR, idx.size());
      gm.primitives.push_back(prim);
    }
    m_.meshes.push_back(gm);
    return gm.name;
  }

  // The weights' animation: one-hot at each frame's time, LINEAR between.
  void WeightsAnimation() {
    std::vector<float> times(frames_);
    for (size_t k = 0; k < frames_; ++k) {
      times[k] = static_cast<float>(static_cast<double>(k) / a_.fps);
    }
    std::vector<uint8_t> weights(frames_ * frames_, 0);
    for (size_t k = 0; k < frames_; ++k) weights[k * frames_ + k] = 255;
    weights.resize((weights.size() + 3) / 4 * 4, 0);  // whole 4-byte elements for the codec
    const ViewCodec kAnim{ViewCodec::Mode::kAttributes, 4};
    const int input = AddAccessor(&m_, View(times.data(), times.size() * 4, 0, kAnim),
                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, frames_,
                                  {times.front()}, {times.back()});
    const int output =
        AddAccessor(&m_, View(weights.data(), weights.size(), 0, kAnim),
                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_SCALAR, frames_ * frames_);
    m_.accessors[output].normalized = true;
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
    m_.animations.push_back(anim);
  }

  const MorphAnimation& a_;
  const AnimationGlbOptions& o_;
  const Mesh& base_;
  const size_t n_;
  const size_t frames_;
  const bool with_normals_;
  const Quantizer quant_;
  tinygltf::Model m_;
  std::vector<ViewCodec> codecs_;
  std::vector<std::array<int16_t, 4>> q0_;  // frame 0's quantized positions
  std::map<std::string, int> attrs_;
  std::vector<std::map<std::string, int>> targets_;
};

Result<meshio::BuiltGlb> BuildModel(const MorphAnimation& a, const AnimationGlbOptions& o) {
  return ModelBuilder(a, o).Build();
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
