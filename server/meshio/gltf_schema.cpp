#include "meshio/gltf_schema.hpp"

#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <string_view>

namespace surfdeform::meshio {
namespace {

using nlohmann::json;

// A number in a message: integers as integers, anything else as JSON has it.
std::string Shown(const json& v) {
  std::string text = v.dump(-1, ' ', false, json::error_handler_t::replace);
  return text.size() > 40 ? text.substr(0, 40) + "..." : text;
}

// The rules of one field: an integer from `min` to `max`, or one of `allowed`.
struct IntegerRule {
  const char* name;
  bool required;
  int64_t min;
  int64_t max;
};

std::string CheckInteger(const json& object, const std::string& path, const IntegerRule& rule,
                         std::string* field) {
  const auto it = object.find(rule.name);
  if (it == object.end()) {
    if (!rule.required) return "";
    *field = path + "." + rule.name;
    return *field + " is required";
  }
  const bool integer =
      it->is_number_integer() ||
      (it->is_number_float() && it->get<double>() == static_cast<double>(it->get<int64_t>()));
  const int64_t value = integer ? it->get<int64_t>() : 0;
  if (integer && value >= rule.min && value <= rule.max) return "";
  *field = path + "." + rule.name;
  return *field + " must be an integer from " + std::to_string(rule.min) + " to " +
         std::to_string(rule.max) + ", got " + Shown(*it);
}

std::string CheckOneOf(const json& object, const std::string& path, const char* name,
                       std::initializer_list<const char*> allowed, std::string* field) {
  const auto it = object.find(name);
  if (it == object.end()) {
    *field = path + "." + name;
    return *field + " is required";
  }
  if (it->is_string() &&
      std::find(allowed.begin(), allowed.end(),
                std::string_view(it->get_ref<const std::string&>())) != allowed.end()) {
    return "";
  }
  *field = path + "." + name;
  std::string list;
  for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
  return *field + " must be one of " + list + ", got " + Shown(*it);
}

// Past these the published limits answer (413 with the limit), not the schema.
constexpr int64_t kMaxIndex = INT32_MAX;
constexpr int64_t kMaxBytes = INT64_MAX / 2;

}  // namespace

std::string FirstGltfSchemaProblem(const json& doc, std::string* field) {
  auto each = [&](const char* array, auto&& check) -> std::string {
    const auto it = doc.find(array);
    if (it == doc.end()) return "";
    if (!it->is_array()) {
      *field = array;
      return *field + " must be an array";
    }
    for (size_t k = 0; k < it->size(); ++k) {
      const std::string path = std::string(array) + "[" + std::to_string(k) + "]";
      const json& object = (*it)[k];
      if (!object.is_object()) {
        *field = path;
        return path + " must be an object";
      }
      if (std::string problem = check(object, path); !problem.empty()) return problem;
    }
    return "";
  };
  std::string problem = each("accessors", [&](const json& a, const std::string& path) {
    for (const IntegerRule& rule :
         {IntegerRule{"count", true, 1, kMaxBytes}, IntegerRule{"bufferView", false, 0, kMaxIndex},
          IntegerRule{"byteOffset", false, 0, kMaxBytes}}) {
      if (std::string p = CheckInteger(a, path, rule, field); !p.empty()) return p;
    }
    static constexpr int64_t kComponentTypes[] = {5120, 5121, 5122, 5123, 5125, 5126};
    const auto type = a.find("componentType");
    const bool known = type != a.end() && type->is_number_integer() &&
                       std::find(std::begin(kComponentTypes), std::end(kComponentTypes),
                                 type->get<int64_t>()) != std::end(kComponentTypes);
    if (!known) {
      *field = path + ".componentType";
      return *field + " must be one of 5120, 5121, 5122, 5123, 5125 (integers) or 5126 (float)" +
             (type == a.end() ? std::string(", and is missing") : ", got " + Shown(*type));
    }
    return CheckOneOf(a, path, "type", {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"},
                      field);
  });
  if (!problem.empty()) return problem;
  problem = each("bufferViews", [&](const json& v, const std::string& path) {
    for (const IntegerRule& rule :
         {IntegerRule{"buffer", true, 0, kMaxIndex}, IntegerRule{"byteLength", true, 1, kMaxBytes},
          IntegerRule{"byteOffset", false, 0, kMaxBytes},
          IntegerRule{"byteStride", false, 4, 252}}) {
      if (std::string p = CheckInteger(v, path, rule, field); !p.empty()) return p;
    }
    return std::string();
  });
  if (!problem.empty()) return problem;
  return each("buffers", [&](const json& b, const std::string& path) {
    return CheckInteger(b, path, IntegerRule{"byteLength", true, 1, kMaxBytes}, field);
  });
}

}  // namespace surfdeform::meshio
