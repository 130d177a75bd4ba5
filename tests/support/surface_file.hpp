// Loads the Bezier surface files of client/web/samples (the surface part of an API
// request) for tests and benchmarks. The API's own JSON mapping lives in proto/.
#pragma once

#include <string>

#include "engine/surface/surface_spec.hpp"

namespace surfdeform::testing {

// Absolute path of a sample file (client/web/samples: the paper surfaces, the bunny).
std::string DataPath(const std::string& name);

// Reads a {"kind": "bezier", ...} file; aborts the test program on a bad file.
BezierSpec LoadBezierFile(const std::string& path);

}  // namespace surfdeform::testing
