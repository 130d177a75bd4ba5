#include "proto/json_object.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

namespace surfdeform::proto {
namespace {

// Levenshtein distance, for "did you mean".
size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// A key as it may appear in a message: printable ASCII only, cut short.
std::string Printable(std::string_view key) {
  std::string out;
  for (char c : key.substr(0, 64)) out.push_back(c >= 0x20 && c < 0x7f ? c : '?');
  if (key.size() > 64) out += "...";
  return out;
}

}  // namespace

std::string JoinPath(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

std::string JoinPath(const std::string& parent, size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

Status Malformed(std::string message, std::string field) {
  return Status(ErrorCode::kMalformed, std::move(message), std::move(field));
}

std::string JsonTypeName(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::object:
      return "an object";
    case nlohmann::json::value_t::array:
      return "an array";
    case nlohmann::json::value_t::string:
      return "a string";
    case nlohmann::json::value_t::boolean:
      return "a boolean";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
    case nlohmann::json::value_t::number_float:
      return "a number";
    default:
      return "an unsupported value";
  }
}

namespace {

Status ReadFixed(const nlohmann::json& value, const std::string& path, double* out, size_t n) {
  if (!value.is_array() || value.size() != n) {
    return Malformed("must be an array of " + std::to_string(n) + " numbers, got " +
                         (value.is_array() ? "an array of " + std::to_string(value.size())
                                           : JsonTypeName(value)),
                     path);
  }
  for (size_t k = 0; k < n; ++k) {
    if (!value[k].is_number()) {
      return Malformed("must be a number, got " + JsonTypeName(value[k]), JoinPath(path, k));
    }
    out[k] = value[k].get<double>();
  }
  return Status::Ok();
}

}  // namespace

Status ReadVec3(const nlohmann::json& value, const std::string& path, Vec3* out) {
  double v[3];
  SURFDEFORM_RETURN_IF_ERROR(ReadFixed(value, path, v, 3));
  *out = Vec3(v[0], v[1], v[2]);
  return Status::Ok();
}

Status ReadVec2(const nlohmann::json& value, const std::string& path, Vec2* out) {
  double v[2];
  SURFDEFORM_RETURN_IF_ERROR(ReadFixed(value, path, v, 2));
  *out = Vec2(v[0], v[1]);
  return Status::Ok();
}

Status ReadPoints(const nlohmann::json& value, const std::string& path, std::vector<Vec3>* out) {
  if (!value.is_array()) {
    return Malformed("must be an array of [x, y, z] points, got " + JsonTypeName(value), path);
  }
  out->clear();
  out->reserve(value.size());
  for (size_t k = 0; k < value.size(); ++k) {
    Vec3 p;
    SURFDEFORM_RETURN_IF_ERROR(ReadVec3(value[k], JoinPath(path, k), &p));
    out->push_back(p);
  }
  return Status::Ok();
}

Status ReadNumbers(const nlohmann::json& value, const std::string& path, std::vector<double>* out) {
  if (!value.is_array()) {
    return Malformed("must be an array of numbers, got " + JsonTypeName(value), path);
  }
  out->clear();
  out->reserve(value.size());
  for (size_t k = 0; k < value.size(); ++k) {
    if (!value[k].is_number()) {
      return Malformed("must be a number, got " + JsonTypeName(value[k]), JoinPath(path, k));
    }
    out->push_back(value[k].get<double>());
  }
  return Status::Ok();
}

Result<JsonObject> JsonObject::Open(const nlohmann::json& value, std::string path) {
  if (!value.is_object()) {
    return Malformed("must be a JSON object, got " + JsonTypeName(value),
                     path.empty() ? "$" : path);
  }
  return JsonObject(&value, std::move(path));
}

const nlohmann::json* JsonObject::Find(std::string_view key) {
  asked_.emplace(key);
  const auto it = json_->find(key);
  return it == json_->end() ? nullptr : &*it;
}

Status JsonObject::Number(std::string_view key, double* out) {
  const nlohmann::json* v = Find(key);
  if (v == nullptr) return Status::Ok();
  if (!v->is_number()) return Malformed("must be a number, got " + JsonTypeName(*v), PathOf(key));
  *out = v->get<double>();
  return Status::Ok();
}

Status JsonObject::Integer(std::string_view key, int* out) {
  const nlohmann::json* v = Find(key);
  if (v == nullptr) return Status::Ok();
  if (!v->is_number()) {
    return Malformed("must be an integer, got " + JsonTypeName(*v), PathOf(key));
  }
  const double d = v->get<double>();
  if (d != std::floor(d) || std::abs(d) > std::numeric_limits<int>::max()) {
    return Status(ErrorCode::kInvalidArgument, "must be an integer in the int range", PathOf(key));
  }
  *out = static_cast<int>(d);
  return Status::Ok();
}

Status JsonObject::Boolean(std::string_view key, bool* out) {
  const nlohmann::json* v = Find(key);
  if (v == nullptr) return Status::Ok();
  if (!v->is_boolean()) {
    return Malformed("must be true or false, got " + JsonTypeName(*v), PathOf(key));
  }
  *out = v->get<bool>();
  return Status::Ok();
}

Status JsonObject::String(std::string_view key, std::string* out) {
  const nlohmann::json* v = Find(key);
  if (v == nullptr) return Status::Ok();
  if (!v->is_string()) return Malformed("must be a string, got " + JsonTypeName(*v), PathOf(key));
  *out = v->get<std::string>();
  return Status::Ok();
}

Status JsonObject::Vector3(std::string_view key, Vec3* out) {
  const nlohmann::json* v = Find(key);
  return v == nullptr ? Status::Ok() : ReadVec3(*v, PathOf(key), out);
}

Status JsonObject::Points(std::string_view key, std::vector<Vec3>* out) {
  const nlohmann::json* v = Find(key);
  return v == nullptr ? Status::Ok() : ReadPoints(*v, PathOf(key), out);
}

Status JsonObject::Numbers(std::string_view key, std::vector<double>* out) {
  const nlohmann::json* v = Find(key);
  return v == nullptr ? Status::Ok() : ReadNumbers(*v, PathOf(key), out);
}

Status JsonObject::Choice(std::string_view key, const std::vector<std::string_view>& names,
                          int* out) {
  const nlohmann::json* v = Find(key);
  if (v == nullptr) return Status::Ok();
  std::string list;
  for (std::string_view n : names) list += (list.empty() ? "\"" : ", \"") + std::string(n) + "\"";
  if (v->is_string()) {
    const std::string& s = v->get_ref<const std::string&>();
    for (size_t k = 0; k < names.size(); ++k) {
      if (s == names[k]) {
        *out = static_cast<int>(k);
        return Status::Ok();
      }
    }
    return Status(ErrorCode::kInvalidArgument,
                  "must be one of " + list + ", got \"" + Printable(s) + "\"", PathOf(key));
  }
  return Malformed("must be one of " + list + ", got " + JsonTypeName(*v), PathOf(key));
}

Status JsonObject::Finish() const {
  for (const auto& [key, value] : json_->items()) {
    if (asked_.count(key) != 0) continue;
    std::string hint;
    size_t best = 3;  // suggest only close names
    for (const std::string& known : asked_) {
      const size_t d = EditDistance(key, known);
      if (d < best) {
        best = d;
        hint = "; did you mean \"" + known + "\"?";
      }
    }
    std::string known_list;
    if (hint.empty()) {
      for (const std::string& known : asked_) {
        known_list += (known_list.empty() ? "" : ", ") + known;
      }
      known_list = " (known fields: " + known_list + ")";
    }
    return Malformed("unknown field \"" + Printable(key) + "\"" + hint + known_list,
                     PathOf(Printable(key)));
  }
  return Status::Ok();
}

}  // namespace surfdeform::proto
