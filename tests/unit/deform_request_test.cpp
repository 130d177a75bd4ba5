// The body forms of POST /v1/deform and /v1/animate (http/deform_request.hpp):
// where the mesh and the parameters are read from, that they are given once,
// and that the request's views stay in the request and its body.
#include "http/deform_request.hpp"

#include <gtest/gtest.h>

#include <string>

namespace surfdeform::http {
namespace {

httplib::Request Post(const std::string& type) {
  httplib::Request req;
  req.method = "POST";
  req.path = "/v1/deform";
  if (!type.empty()) req.headers.emplace("Content-Type", type);
  return req;
}

bool Within(std::string_view view, const std::string& owner) {
  return view.data() >= owner.data() && view.data() + view.size() <= owner.data() + owner.size();
}

TEST(DeformRequest, RawMeshWithParametersInTheHeaderOrTheQuery) {
  DeformBody body;
  body.raw = "v 0 0 0\n";
  httplib::Request header = Post("application/octet-stream");
  header.headers.emplace("X-Surfdeform-Params", R"({"surface_id":"a"})");
  header.headers.emplace("Accept", "model/gltf-binary");
  header.headers.emplace("X-Surfdeform-Surface-Id", "a");
  auto h = DeformRequestOf(header, body);
  ASSERT_TRUE(h.ok()) << h.status().ToString();
  EXPECT_EQ(h->mesh, body.raw);
  EXPECT_EQ(h->params, R"({"surface_id":"a"})");
  EXPECT_TRUE(Within(h->params, header.headers.find("X-Surfdeform-Params")->second));
  EXPECT_EQ(h->accept, "model/gltf-binary");
  EXPECT_EQ(h->routed_surface_id, "a");

  httplib::Request query = Post("application/octet-stream");
  query.params.emplace("params", R"({"surface_id":"b"})");
  query.params.emplace("surface_id", "b");
  auto q = DeformRequestOf(query, body);
  ASSERT_TRUE(q.ok()) << q.status().ToString();
  EXPECT_EQ(q->params, R"({"surface_id":"b"})");
  EXPECT_TRUE(Within(q->params, query.params.find("params")->second));
  EXPECT_EQ(q->routed_surface_id, "b");
}

TEST(DeformRequest, AJsonBodyIsTheParametersAndAFormItsParts) {
  DeformBody json;
  json.raw = R"({"model_id":"m","surface_id":"a"})";
  auto j = DeformRequestOf(Post("application/json; charset=utf-8"), json);
  ASSERT_TRUE(j.ok()) << j.status().ToString();
  EXPECT_TRUE(j->mesh.empty());
  EXPECT_EQ(j->params, json.raw);

  httplib::Request form = Post("multipart/form-data; boundary=x");
  DeformBody parts;
  httplib::MultipartFormData mesh{"mesh", "v 1 1 1\n", "m.obj", "text/plain"};
  httplib::MultipartFormData params{"params", R"({"surface_id":"c"})", "", "application/json"};
  parts.parts.emplace("mesh", mesh);
  parts.parts.emplace("params", params);
  auto f = DeformRequestOf(form, parts);
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  EXPECT_EQ(f->mesh, "v 1 1 1\n");
  EXPECT_EQ(f->params, R"({"surface_id":"c"})");
  EXPECT_TRUE(Within(f->params, parts.parts.find("params")->second.content));
}

TEST(DeformRequest, ParametersGivenTwiceOrNotAtAllAreRefused) {
  DeformBody body;
  body.raw = "v 0 0 0\n";
  httplib::Request both = Post("application/octet-stream");
  both.headers.emplace("X-Surfdeform-Params", "{}");
  both.params.emplace("params", "{}");
  auto twice = DeformRequestOf(both, body);
  ASSERT_FALSE(twice.ok());
  EXPECT_EQ(twice.status().code(), ErrorCode::kMalformed);
  EXPECT_EQ(twice.status().field(), "params");
  EXPECT_NE(twice.status().message().find("given 2 times"), std::string::npos);

  auto none = DeformRequestOf(Post("application/octet-stream"), body);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.status().field(), "params");

  auto urlencoded = DeformRequestOf(Post("application/x-www-form-urlencoded"), body);
  ASSERT_FALSE(urlencoded.ok());
  EXPECT_EQ(urlencoded.status().code(), ErrorCode::kUnsupportedFormat);

  httplib::Request form = Post("multipart/form-data; boundary=x");
  DeformBody two_meshes;
  two_meshes.parts.emplace("mesh", httplib::MultipartFormData{"mesh", "a", "", ""});
  two_meshes.parts.emplace("mesh", httplib::MultipartFormData{"mesh", "b", "", ""});
  EXPECT_EQ(DeformRequestOf(form, two_meshes).status().field(), "mesh");
}

TEST(DeformRequest, AnUploadIsTheRawBodyOrOneMeshPart) {
  DeformBody raw;
  raw.raw = "ply\n";
  auto r = UploadedMesh(Post("application/octet-stream"), raw);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r, "ply\n");
  DeformBody form;
  form.parts.emplace("mesh", httplib::MultipartFormData{"mesh", "solid", "a.stl", ""});
  auto f = UploadedMesh(Post("multipart/form-data; boundary=x"), form);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(*f, "solid");
  form.parts.emplace("params", httplib::MultipartFormData{"params", "{}", "", ""});
  EXPECT_FALSE(UploadedMesh(Post("multipart/form-data; boundary=x"), form).ok());
}

}  // namespace
}  // namespace surfdeform::http
