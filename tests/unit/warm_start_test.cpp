// The warm-start room alone: which surfaces share a shape, which named
// surface a new flattening may start from (and why not), and the reply's
// account of it.
#include "service/warm_start.hpp"

#include <gtest/gtest.h>

namespace surfdeform {
namespace {

using nlohmann::json;

proto::CreateSurfaceRequest Create(const std::string& text) {
  auto r = proto::ParseCreateSurfaceRequest(json::parse(text));
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? *r : proto::CreateSurfaceRequest{};
}

const char kPatch[] =
    R"("surface":{"kind":"bezier","degree_u":1,"degree_v":1,"control_points":[[0,0,0],[1,0,0],[0,1,0],[1,1,LIFT]]})";

std::string Patch(const char* lift, const std::string& rest = R"(,"sampling":{"nu":8,"nv":8})") {
  std::string s = kPatch;
  s.replace(s.find("LIFT"), 4, lift);
  return "{" + s + rest + "}";
}

TEST(WarmStart, SameShapeComparesKindDegreesAndControlGrid) {
  BezierSpec a, b;
  a.degree_u = a.degree_v = b.degree_u = b.degree_v = 1;
  a.control_points.resize(4);
  b.control_points.resize(4);
  EXPECT_TRUE(SameShape(a, b));
  b.degree_u = 2;
  b.control_points.resize(6);
  EXPECT_FALSE(SameShape(a, b));
  EXPECT_FALSE(SameShape(a, CylinderSpec{}));
  EXPECT_TRUE(SameShape(CylinderSpec{}, CylinderSpec{}));
  GridSpec g, h;
  g.nu = h.nu = 4;
  g.nv = 4;
  h.nv = 5;
  EXPECT_FALSE(SameShape(g, h));
}

TEST(WarmStart, ASurfaceOfTheSameShapeIsTheStartAndAnyOtherSaysWhyNot) {
  ServiceLimits limits;
  SurfaceStore store(limits, 1, nullptr);
  const RequestClock clock(60000);
  bool hit = false;
  auto first = store.Flattened(Create(Patch("0.2")).request, clock, &hit);
  ASSERT_TRUE(first.ok());
  const std::string id = (*first)->id;
  const std::string from = R"(,"warm_start":")" + id + "\"";

  WarmStart w = WarmStartFor(Create(Patch("0.25", R"(,"sampling":{"nu":8,"nv":8})" + from)), store);
  EXPECT_EQ(w.entry, *first);
  EXPECT_TRUE(w.reason.empty());
  w = WarmStartFor(Create(Patch("0.25", R"(,"sampling":{"nu":9,"nv":8})" + from)), store);
  EXPECT_EQ(w.entry, nullptr);
  EXPECT_EQ(w.reason, "another sampling grid");
  w = WarmStartFor(
      Create(Patch("0.25", R"(,"sampling":{"nu":8,"nv":8},"flatten":{"range":2})" + from)), store);
  EXPECT_EQ(w.reason, "other flattening options");
  w = WarmStartFor(
      Create(R"({"surface":{"kind":"cylinder"},"sampling":{"nu":8,"nv":8})" + from + "}"), store);
  EXPECT_NE(w.reason.find("shape"), std::string::npos);
  w = WarmStartFor(Create(Patch("0.25", R"(,"warm_start":"0123456789abcdef0123456789abcdef")")),
                   store);
  EXPECT_NE(w.reason.find("unknown"), std::string::npos);
  EXPECT_TRUE(WarmStartFor(Create(Patch("0.25")), store).from.empty());

  // The account: used (with the iterations), or not (with why).
  WarmStart used{id, *first, ""};
  json j = WarmStartJson(used, **first, false);
  EXPECT_EQ(j["used"], true);
  EXPECT_TRUE(j.contains("iterations_saved_estimate"));
  j = WarmStartJson(used, **first, true);
  EXPECT_EQ(j["used"], false);
  EXPECT_EQ(j["reason"], "the surface was flattened already");
}

}  // namespace
}  // namespace surfdeform
