// Surface ids pinned byte for byte: a surface's id is the content hash of
// its canonical JSON, and ids live on in clients, caches, Redis and disk.
// A change to how a kind's fields are read, written or defaulted must not
// change them. Every kind, every field given once, the samples as shipped,
// and each kind with its defaults; the ids below were made by the code
// before the surface kinds were described once.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "proto/api.hpp"
#include "support/surface_file.hpp"

namespace surfdeform::proto {
namespace {

using nlohmann::json;

std::string IdOf(const json& body) {
  auto request = ParseSurfaceRequest(body);
  EXPECT_TRUE(request.ok()) << body.dump() << ": " << request.status().ToString();
  return request.ok() ? SurfaceId(*request) : "";
}

json Sample(const std::string& name) {
  std::ifstream in(testing::DataPath(name));
  std::stringstream text;
  text << in.rdbuf();
  json surface = json::parse(text.str());
  surface.erase("description");  // the file's own note, not part of the API
  return surface;
}

// Every kind with each of its fields set (not the default), a frame, the
// sampling and flattening options.
const std::vector<std::pair<const char*, const char*>> kEveryField = {
    {"bezier", R"({"surface":{"kind":"bezier","degree_u":1,"degree_v":2,
        "control_points":[[0,0,0],[1,0,0.5],[0,0.5,0.2],[1,0.5,1],[0,1,0],[1,1,0.3]]},
        "sampling":{"nu":12,"nv":10},"flatten":{"method":"paper","range":2}})"},
    {"bspline", R"({"surface":{"kind":"bspline","degree_u":1,"degree_v":1,"count_u":2,"count_v":2,
        "control_points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1]}})"},
    {"nurbs", R"({"surface":{"kind":"nurbs","degree_u":1,"degree_v":1,"count_u":2,"count_v":2,
        "control_points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],
        "weights":[1,2,1,1]}})"},
    {"cylinder", R"({"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":200,
        "frame":{"origin":[1,2,3],"x_axis":[1,0,0],"z_axis":[0,1,0]}}})"},
    {"cone",
     R"({"surface":{"kind":"cone","radius_bottom":2,"radius_top":1,"height":1.5,"angle_deg":270}})"},
    {"sphere", R"({"surface":{"kind":"sphere","radius":2}})"},
    {"torus", R"({"surface":{"kind":"torus","major_radius":3,"minor_radius":0.5}})"},
    {"wave", R"({"surface":{"kind":"wave","length":4,"width":1.5,"amplitude":0.25,"wavelength":2,
        "time":0.5}})"},
    {"grid",
     R"({"surface":{"kind":"grid","nu":2,"nv":2,"points":[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}})"},
    {"mesh", R"({"surface":{"kind":"mesh","model_id":"0123456789abcdef0123456789abcdef"}})"},
};

// Made by the code as it was (see the file's comment); the cone sample's id
// is also the one bench/behaviour_diff.sh records for the server of 3225f63.
const std::vector<std::pair<const char*, const char*>> kPinned = {
    {"bezier", "16b1c97193aeef4c1d831f55a9b2ab49"},
    {"bspline", "69b25520e1a251fd67ba3a428e82e413"},
    {"nurbs", "7a05c29524b5656cf5c0e4ee929aaede"},
    {"cylinder", "56d460d509b483b90d5a9df870d97aef"},
    {"cone", "68ccee084be496bd7af6f6d43ae4c354"},
    {"sphere", "e015cec63e3546ae3d30620a94fe3ed9"},
    {"torus", "582492a64e56e51b7e9d8cf069aa5450"},
    {"wave", "828d3eab62b25df6782d49d3140cfbc3"},
    {"grid", "99158265e89405e03f8acf9e66b1f3e6"},
    {"mesh", "a2ae174896b9f9e90f74b90352634791"},
    {"bezier defaults", "cb716c0e625aab2d704ee7446ebedc69"},
    {"cylinder defaults", "c8a76e4c7d13548db191c31f9de97dd0"},
    {"cone defaults", "fe9203db9dd841c9a5e07952e44b1dac"},
    {"sphere defaults", "2031c8875b2c31843f16f013dc842bf9"},
    {"torus defaults", "eb73116c42af308b491fba10a2948c47"},
    {"wave defaults", "b1c32b312e34cac52f0330bf1d770802"},
    {"figure8.json", "5aa6879eff6c5236fabfbfaeef9a47e3"},
    {"figure9.json", "7919ed270c9cf356668f193adc8bb3b4"},
    {"figure10.json", "45ab9b0aa3b82492b465d26896b91e10"},
    {"cone.json", "14ab6b45b84b6388c590fe080ed8f25c"},
    {"bottle.json", "90c589ed70019ba7981e74bd812efd96"},
};

TEST(SurfaceIds, AreTheSameAsBefore) {
  std::vector<std::pair<std::string, std::string>> now;
  for (const auto& [name, text] : kEveryField) now.emplace_back(name, IdOf(json::parse(text)));
  for (const char* kind : {"bezier", "cylinder", "cone", "sphere", "torus", "wave"}) {
    json body = {{"surface", {{"kind", kind}}}};
    if (std::string(kind) == "bezier") {
      body["surface"]["degree_u"] = 1;
      body["surface"]["degree_v"] = 1;
      body["surface"]["control_points"] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}};
    }
    now.emplace_back(std::string(kind) + " defaults", IdOf(body));
  }
  for (const char* sample :
       {"figure8.json", "figure9.json", "figure10.json", "cone.json", "bottle.json"}) {
    now.emplace_back(sample, IdOf({{"surface", Sample(sample)}}));
  }
  std::string table;
  for (const auto& [name, id] : now) table += "    {\"" + name + "\", \"" + id + "\"},\n";
  ASSERT_EQ(now.size(), kPinned.size()) << "ids now:\n" << table;
  for (size_t k = 0; k < now.size(); ++k) {
    EXPECT_EQ(now[k].first, kPinned[k].first);
    EXPECT_EQ(now[k].second, kPinned[k].second) << now[k].first << "; ids now:\n" << table;
  }
}

}  // namespace
}  // namespace surfdeform::proto
