// Internal: a GLB whose buffer views are compressed with
// EXT_meshopt_compression, shared by the animation writer
// (animation_glb.cpp) and the single-frame writer (quantized_glb.cpp).
//
// A writer builds the uncompressed GLB as a tinygltf::Model and says, per
// buffer view, how meshoptimizer's codecs would compress it (ViewCodec).
// Finish() turns the model into its JSON document and binary buffer; Glb()
// writes them as they are (the uncompressed twin, which validators that do
// not know the extension can check), Compress() with the views compressed
// and a fallback buffer that has no data.
#pragma once

#include <tiny_gltf.h>

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.hpp"

namespace surfdeform::meshio {

// How a buffer view is compressed with EXT_meshopt_compression.
struct ViewCodec {
  enum class Mode { kNone, kAttributes, kTriangles };
  ViewCodec() = default;
  ViewCodec(Mode m, int s) : mode(m), stride(s) {}

  Mode mode = Mode::kNone;
  int stride = 0;  // the codec's element size (4 for triangles)
  // With a filter ("OCTAHEDRAL"), the codec compresses `filtered`, which
  // the filter decodes to the view's data.
  const char* filter = nullptr;
  std::vector<unsigned char> filtered;
};

// The uncompressed GLB as its JSON document and binary buffer, and how each
// of its buffer views would be compressed.
struct BuiltGlb {
  nlohmann::json doc;
  std::vector<unsigned char> bin;
  std::vector<ViewCodec> codecs;  // per buffer view (missing ones: kNone)
  std::string_view bin_view() const {
    return {reinterpret_cast<const char*>(bin.data()), bin.size()};
  }
};

// The scene of quantized positions (KHR_mesh_quantization): one node of
// mesh 0 whose translation and uniform scale undo them (an integer q
// stands for q / 32767 * scale + origin).
void AddQuantizedNode(tinygltf::Model* model, const std::string& name,
                      const std::array<double, 3>& origin, double scale);

// The model's document and buffer 0 (taken from the model, not copied).
Result<BuiltGlb> Finish(tinygltf::Model* model, std::vector<ViewCodec> codecs);

// A GLB of this document and binary chunk.
std::string Glb(const nlohmann::json& doc, std::string_view bin);

// The GLB with its compressible views compressed, on up to `threads` threads.
Result<std::string> Compress(BuiltGlb built, int threads);

// meshoptimizer's index codec may start a triangle at another of its corners
// (same triangle, same winding): writers store the order it decodes to, so
// that the compressed file and its uncompressed twin hold the same data.
Status AsTheCodecDecodes(std::vector<uint32_t>* indices);

}  // namespace surfdeform::meshio
