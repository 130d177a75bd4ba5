// Writing an animation as one GLB: one mesh whose frames are morph targets,
// and an animation of its weights (docs/ARCHITECTURE.md, "Conventions the code relies on").
//
// The layout, which three.js's GLTFLoader plays (AnimationMixer) and the
// Khronos validator accepts:
//  - one node, one mesh, one primitive per MeshGroup; the primitives share
//    the vertex accessors and the targets;
//  - positions quantized (KHR_mesh_quantization): 16-bit normalized
//    integers over the bounding box of every frame, the node's translation and
//    uniform scale undoing it. The base is frame 0; target k holds
//    Q(frame k) - Q(frame 0) in the same integers, so base + target k is
//    frame k's quantized position exactly (error at most half a step, 1 /
//    65532 of the box's largest side). Target 0 is all zeros (an accessor
//    with no buffer view);
//  - normals, when the model has them: frame 0's as floats, and each frame's
//    change as floats rounded to 2^-12 (which the renderer renormalises);
//  - texture coordinates and colours as floats, from frame 0; tangents are
//    not written (they would go stale as the surface moves);
//  - the animation: at frame k's time k / fps, weight k is 1 and the others 0
//    (LINEAR between frames), as normalized unsigned bytes;
//  - kMeshopt: every vertex, index and animation buffer view compressed with
//    EXT_meshopt_compression (meshoptimizer's codecs, no filters), with a
//    fallback buffer that has no data. kNone: the same file with the views
//    uncompressed (for validators that do not know the extension).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/mesh.hpp"
#include "meshio/mesh_export.hpp"

namespace surfdeform {

enum class AnimationCompression { kMeshopt, kNone };
inline constexpr EnumEntry<AnimationCompression> kAnimationCompressions[] = {
    {AnimationCompression::kMeshopt, "meshopt",
     "EXT_meshopt_compression on every vertex, index and animation buffer (the default)"},
    {AnimationCompression::kNone, "none", "the same GLB uncompressed"},
};

using Vec3f = Eigen::Vector3f;

struct MorphAnimation {
  // Topology, groups, texture coordinates and colours (positions and normals
  // are taken from the frames).
  const Mesh* base = nullptr;
  std::vector<std::vector<Vec3f>> positions;  // per frame, one per vertex of base
  std::vector<std::vector<Vec3f>> normals;    // per frame; empty when base has no normals
  double fps = 30.0;
};

struct AnimationGlbOptions {
  AnimationCompression compression = AnimationCompression::kMeshopt;
  ExportOptions look;  // materials (names, or the input's glTF look)
  int threads = 0;     // for compressing the buffer views; 0 = one per core
};

// Errors: kInvalidArgument for frames that do not match the base or values
// that are not finite; kInternal if GLB writing fails.
Result<std::string> WriteAnimationGlb(const MorphAnimation& animation,
                                      const AnimationGlbOptions& options);

}  // namespace surfdeform
