#include "support/surface_file.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

namespace surfdeform::testing {

std::string DataPath(const std::string& name) {
  return std::string(SURFDEFORM_TEST_DATA_DIR) + "/" + name;
}

BezierSpec LoadBezierFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "cannot open %s\n", path.c_str());
    std::abort();
  }
  const nlohmann::json j = nlohmann::json::parse(in);
  BezierSpec spec;
  spec.degree_u = j.at("degree_u").get<int>();
  spec.degree_v = j.at("degree_v").get<int>();
  for (const auto& p : j.at("control_points")) {
    spec.control_points.emplace_back(p.at(0).get<double>(), p.at(1).get<double>(),
                                     p.at(2).get<double>());
  }
  return spec;
}

}  // namespace surfdeform::testing
