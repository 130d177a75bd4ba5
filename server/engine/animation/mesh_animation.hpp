// An animation whose keyframes are meshes of one topology (a
// cloth simulation exported frame by frame), flattened frame after frame.
//
// Every frame's mesh is the keys' vertices interpolated (animation.hpp's
// rules, vertex coordinate by coordinate). Frame 0 is flattened as the
// first key alone would be (FlattenMesh: the conformal start, the canonical
// frame), so that deformations through it match POST /v1/deform on that
// mesh bit for bit. Every later frame starts from the sheet before it
// (MeshFlattener, keeping frame 0's vertex pairs and factor): its distances
// are measured along that layout (near-isometric for a mesh that moved a
// little), the solve starts from the last sheets carried on, and the result
// is turned back onto the sheet before (the rotation of the best affine map
// between them). The sheet then stays with the mesh's material from frame
// to frame (a model placed on it stays on the same part of the cloth)
// instead of turning where the canonical frame's principal axes swap. A
// frame whose triangle collapses between the keys is an error naming the
// frame and the triangle.
#pragma once

#include <functional>

#include "base/status.hpp"
#include "engine/animation/animation.hpp"

namespace surfdeform {

// Flattens every frame of a valid spec whose keyframes are meshes;
// `frame_mesh(k)` gives frame k's surface (a MeshSpec with its `disk`).
// Sheets are sampled on `sampling` over each frame's flat mesh.
Result<AnimatedSheets> FlattenMeshAnimation(const AnimationSpec& spec,
                                            const SamplingOptions& sampling,
                                            const FlattenOptions& options,
                                            const FrameProgress& progress,
                                            const std::function<MeshSpec(int)>& frame_mesh);

}  // namespace surfdeform
