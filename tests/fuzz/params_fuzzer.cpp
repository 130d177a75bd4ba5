// libFuzzer target: request JSON into the request types, as the service
// reads it (the depth limit first, then the parsers of POST /v1/surfaces,
// the deformation parameters, POST /v1/animate and POST /v1/surfaces/{id}/map).
// Whatever is accepted is written back (proto::ToJson, as the client builds
// its requests), through JSON text, and must read back into a request that
// writes the same: the target aborts otherwise. An accepted animation's first
// and last frames are interpolated and its content id taken. Build with
// SURFDEFORM_FUZZ=ON and clang (see tests/fuzz/run.sh).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "engine/animation/animation.hpp"
#include "json/bounded_json.hpp"
#include "proto/api.hpp"
#include "proto/json_object.hpp"
#include "proto/map_api.hpp"

namespace {

// `request`, written and read back by `parse`, writes the same.
template <typename Request, typename Parse>
void ExpectReadsBack(const Request& request, Parse parse) {
  const nlohmann::json written = surfdeform::proto::ToJson(request);
  auto again = parse(nlohmann::json::parse(written.dump()));
  if (!again.ok() || surfdeform::proto::ToJson(*again) != written) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto json = surfdeform::ParseBoundedJson(text, surfdeform::JsonLimits{}, "params");
  if (!json.ok()) return 0;
  (void)surfdeform::proto::ParseSurfaceRequest(*json);
  if (auto create = surfdeform::proto::ParseCreateSurfaceRequest(*json); create.ok()) {
    ExpectReadsBack(*create, surfdeform::proto::ParseCreateSurfaceRequest);
  }
  if (auto deform = surfdeform::proto::ParseDeformParams(*json); deform.ok()) {
    ExpectReadsBack(*deform, surfdeform::proto::ParseDeformParams);
  }
  if (auto map = surfdeform::proto::ParseMapRequest(*json, surfdeform::proto::MapLimits{});
      map.ok()) {
    ExpectReadsBack(*map, [](const nlohmann::json& body) {
      return surfdeform::proto::ParseMapRequest(body, surfdeform::proto::kNoMapLimits);
    });
  }
  if (auto animate = surfdeform::proto::ParseAnimateParams(*json); animate.ok()) {
    ExpectReadsBack(*animate, surfdeform::proto::ParseAnimateParams);
    const surfdeform::AnimationSpec& spec = animate->animation.animation;
    (void)surfdeform::SurfaceAtFrame(spec, 0);
    (void)surfdeform::SurfaceAtFrame(spec, spec.frames - 1);
    (void)surfdeform::proto::AnimationId(animate->animation);
  }
  // The replies' JSON is dumped with replacement of invalid UTF-8, as ever.
  (void)json->dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
  return 0;
}
