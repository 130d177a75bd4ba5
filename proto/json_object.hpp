// Strict reading of request JSON: every field is looked up by name with its
// expected type, and whatever is left unread at the end is an error (a typo
// must not be silently ignored). Every error names the JSON path of the
// offending field ("placement.scale", "surface.control_points[3][1]").
//
// Type errors (a string where a number belongs, an unknown field) are
// kMalformed; values of the right type but out of range are left to the
// engine's validation (kInvalidArgument), which knows the rules.
#pragma once

#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "base/enum_table.hpp"
#include "base/status.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform::proto {

// "a.b" or "a[3]" from a parent path and a key or index.
std::string JoinPath(const std::string& parent, std::string_view key);
std::string JoinPath(const std::string& parent, size_t index);

// "a string", "an array", ...: for messages.
std::string JsonTypeName(const nlohmann::json& value);

Status Malformed(std::string message, std::string field);

// Reads 3 numbers [x, y, z] (or 2 for Vec2) at `path`.
Status ReadVec3(const nlohmann::json& value, const std::string& path, Vec3* out);
Status ReadVec2(const nlohmann::json& value, const std::string& path, Vec2* out);
Status ReadPoints(const nlohmann::json& value, const std::string& path, std::vector<Vec3>* out);
Status ReadNumbers(const nlohmann::json& value, const std::string& path, std::vector<double>* out);

class JsonObject {
 public:
  // kMalformed unless `value` is an object. `value` must outlive this.
  static Result<JsonObject> Open(const nlohmann::json& value, std::string path);

  // The field's value (marked as read), or nullptr when absent.
  const nlohmann::json* Find(std::string_view key);
  std::string PathOf(std::string_view key) const { return JoinPath(path_, key); }
  const std::string& path() const { return path_; }

  // Optional fields: when absent *out is left as it is.
  Status Number(std::string_view key, double* out);
  Status Integer(std::string_view key, int* out);
  Status Boolean(std::string_view key, bool* out);
  Status String(std::string_view key, std::string* out);
  Status Vector3(std::string_view key, Vec3* out);
  Status Points(std::string_view key, std::vector<Vec3>* out);
  Status Numbers(std::string_view key, std::vector<double>* out);
  // A string that must be one of `names`; *out becomes its index.
  Status Choice(std::string_view key, const std::vector<std::string_view>& names, int* out);
  // The same over an enum's table: *out = the value named (left as it is
  // when the key is absent).
  template <typename E>
  Status Choice(std::string_view key, std::span<const EnumEntry<E>> table, E* out) {
    std::vector<std::string_view> names;
    for (const EnumEntry<E>& e : table) names.push_back(e.name);
    int index = -1;
    SURFDEFORM_RETURN_IF_ERROR(Choice(key, names, &index));
    if (index >= 0) *out = table[index].value;
    return Status::Ok();
  }

  // kMalformed naming the first field that no lookup asked for, with the
  // closest name that was asked for ("did you mean ...").
  Status Finish() const;

 private:
  JsonObject(const nlohmann::json* json, std::string path) : json_(json), path_(std::move(path)) {}
  const nlohmann::json* json_;
  std::string path_;
  std::set<std::string, std::less<>> asked_;
};

}  // namespace surfdeform::proto
