// Draco's encoder settings ("output.draco" of POST /v1/deform): plain
// vocabulary, which the API's request types (proto/) share with the
// exporters (mesh_export.hpp).
#pragma once

#include "base/status.hpp"

namespace surfdeform {

struct DracoOptions {
  // Quantization bits per attribute (Draco's own defaults are 11 / 8 / 10 / 8;
  // these are chosen by measurement: see BENCHMARKS.md).
  int position_bits = 14;
  int normal_bits = 10;
  int uv_bits = 12;
  int color_bits = 8;
  int speed = 5;            // Draco encoder speed 0 (smallest) .. 10 (fastest)
  bool sequential = false;  // keep the vertex order (larger files)
};

// kInvalidArgument naming the field ("output.draco.position_bits").
Status ValidateDracoOptions(const DracoOptions& options);

}  // namespace surfdeform
