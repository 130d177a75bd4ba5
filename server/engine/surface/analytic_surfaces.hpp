// Closed-form surface kinds: cylinder, cone, sphere, torus and wave patches.
// Each is built from an already validated spec (see MakeSurface) and an
// orthonormal frame; derivatives are exact.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "engine/surface/surface.hpp"
#include "engine/surface/surface_spec.hpp"

namespace surfdeform {

// A rigid placement: world = origin + rotation * local.
struct RigidFrame {
  Vec3 origin = Vec3::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

std::unique_ptr<Surface> MakeCylinder(const CylinderSpec& spec, const RigidFrame& frame);
std::unique_ptr<Surface> MakeCone(const ConeSpec& spec, const RigidFrame& frame);
std::unique_ptr<Surface> MakeSphere(const SphereSpec& spec, const RigidFrame& frame);
std::unique_ptr<Surface> MakeTorus(const TorusSpec& spec, const RigidFrame& frame);
std::unique_ptr<Surface> MakeWave(const WaveSpec& spec, const RigidFrame& frame);

}  // namespace surfdeform
