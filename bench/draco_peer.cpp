#include "draco_peer.hpp"

#include <draco/compression/encode.h>
#include <draco/io/ply_decoder.h>

#include <chrono>

#include "meshio/mesh_export.hpp"

namespace surfdeform::bench {

struct DracoPeer::Impl {
  draco::Mesh mesh;
  draco::Encoder encoder;
  bool ok = false;
};

DracoPeer::DracoPeer(const std::string& ply) : impl_(new Impl) {
  draco::DecoderBuffer in;
  in.Init(ply.data(), ply.size());
  if (!draco::PlyDecoder().DecodeFromBuffer(&in, &impl_->mesh).ok()) return;
  const DracoOptions defaults;  // the service's defaults
  using GA = draco::GeometryAttribute;
  draco::Encoder& e = impl_->encoder;
  e.SetAttributeQuantization(GA::POSITION, defaults.position_bits);
  e.SetAttributeQuantization(GA::NORMAL, defaults.normal_bits);
  e.SetAttributeQuantization(GA::TEX_COORD, defaults.uv_bits);
  e.SetAttributeQuantization(GA::COLOR, defaults.color_bits);
  e.SetSpeedOptions(defaults.speed, defaults.speed);
  e.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
  impl_->ok = true;
}

DracoPeer::~DracoPeer() { delete impl_; }

bool DracoPeer::ok() const { return impl_->ok; }

double DracoPeer::EncodeMs() {
  draco::EncoderBuffer out;
  const auto t0 = std::chrono::steady_clock::now();
  if (!impl_->encoder.EncodeMeshToBuffer(impl_->mesh, &out).ok()) return -1.0;
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool DracoPeer::Encode(std::string* out) {
  draco::EncoderBuffer buffer;
  if (!impl_->encoder.EncodeMeshToBuffer(impl_->mesh, &buffer).ok()) return false;
  out->assign(buffer.data(), buffer.size());
  return true;
}

}  // namespace surfdeform::bench
