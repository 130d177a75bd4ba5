// A surface kind's fields in JSON, read and written as VisitFields
// (engine/surface_fields.hpp) lists them: the one description of each kind
// that parsing, writing, the animations' numbers and the store's estimate
// share. ReadSurface and SurfaceJson (api.hpp) use these for every kind.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/status.hpp"
#include "engine/surface/surface_fields.hpp"
#include "proto/json_object.hpp"

namespace surfdeform::proto {

// The optional frame object `name` of `o` (origin, x_axis, z_axis), into
// *frame; when absent *frame is left as it is.
Status ReadFrame(JsonObject& o, const char* name, Frame* frame);
nlohmann::json FrameJson(const Frame& frame);
nlohmann::json PointsJson(const std::vector<Vec3>& points);

// Reads the fields of `o` into a spec, the first error kept (later fields
// are then not read).
class FieldReader {
 public:
  explicit FieldReader(JsonObject& o) : o_(o) {}
  void Integer(const char* name, int& v) {
    Read([&] { return o_.Integer(name, &v); });
  }
  void Number(const char* name, double& v) {
    Read([&] { return o_.Number(name, &v); });
  }
  void Numbers(const char* name, std::vector<double>& v) {
    Read([&] { return o_.Numbers(name, &v); });
  }
  void Points(const char* name, std::vector<Vec3>& v) {
    Read([&] { return o_.Points(name, &v); });
  }
  void Flag(const char* name, bool& v) {
    Read([&] { return o_.Boolean(name, &v); });
  }
  void Placement(const char* name, Frame& v) {
    Read([&] { return ReadFrame(o_, name, &v); });
  }
  void Text(const char* name, std::string& v) {
    Read([&] { return o_.String(name, &v); });
  }
  const Status& status() const { return status_; }

 private:
  template <typename F>
  void Read(const F& read) {
    if (status_.ok()) status_ = read();
  }
  JsonObject& o_;
  Status status_;
};

// Writes a spec's fields into a JSON object (a flag only when set).
class FieldWriter {
 public:
  explicit FieldWriter(nlohmann::json& j) : j_(j) {}
  void Integer(const char* name, int v) { j_[name] = v; }
  void Number(const char* name, double v) { j_[name] = v; }
  void Numbers(const char* name, const std::vector<double>& v) { j_[name] = v; }
  void Points(const char* name, const std::vector<Vec3>& v) { j_[name] = PointsJson(v); }
  void Flag(const char* name, bool v) {
    if (v) j_[name] = true;  // absent when false: keys stay as they were
  }
  void Placement(const char* name, const Frame& v) { j_[name] = FrameJson(v); }
  void Text(const char* name, const std::string& v) { j_[name] = v; }

 private:
  nlohmann::json& j_;
};

// A spec of one kind (any with a VisitFields) from the fields of `o`.
template <typename S>
Status ReadFields(JsonObject& o, S& s) {
  FieldReader reader(o);
  VisitFields(s, reader);
  return reader.status();
}

// The fields of a spec of one kind, added to the object *j.
template <typename S>
void WriteFields(const S& s, nlohmann::json* j) {
  VisitFields(s, FieldWriter(*j));
}

}  // namespace surfdeform::proto
