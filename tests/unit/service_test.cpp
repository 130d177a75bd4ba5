// The service without HTTP: requests end to end, limits, the cache through it.
#include "service/service.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "fuzz/estimate_input.hpp"
#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"
#include "service/answer_cache.hpp"
#include "support/test_meshes.hpp"

namespace surfdeform {
namespace {

// A reply's stats as the client reads them: the header's JSON.
nlohmann::json StatsOf(const Reply& r) { return nlohmann::json::parse(StatsHeaderText(r)); }

using nlohmann::json;

const char kCylinder[] =
    R"({"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},"sampling":{"nu":8,"nv":8}})";

// No answers kept: for tests of the work a repeated request does.
ServiceOptions EveryAnswerMade() {
  ServiceOptions o;
  o.limits.answer_cache_bytes = 0;
  return o;
}

std::string PlateObj() {
  auto bytes = ExportMesh(testing::ThinPlate(1.0, 0.5, 0.05), MeshFormat::kObj);
  EXPECT_TRUE(bytes.ok());
  return bytes.ok() ? *bytes : std::string();
}

TEST(Service, FlattensOnceAndServesTheSheet) {
  Service service({});
  auto first = service.CreateSurface(kCylinder);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  EXPECT_FALSE(first->cache_hit);
  const json summary = json::parse(first->body);
  const std::string id = summary.at("id");
  EXPECT_EQ(summary.at("method"), "exact");
  EXPECT_EQ(summary.at("quality").at("folded_cells"), 0);

  auto second = service.CreateSurface(kCylinder);
  ASSERT_TRUE(second.ok());
  EXPECT_TRUE(second->cache_hit);
  EXPECT_EQ(json::parse(second->body).at("id"), id);

  auto sheet = service.GetSurface(id);
  ASSERT_TRUE(sheet.ok());
  const json j = json::parse(sheet->body);
  ASSERT_EQ(j.at("flat").size(), 64u);
  ASSERT_EQ(j.at("points").size(), 64u);
  // The unrolled half cylinder: pi * r wide along u, height along v.
  const json& last = j.at("flat")[63];
  EXPECT_NEAR(last[0].get<double>(), 3.14159265358979 * 2, 1e-9);
  EXPECT_NEAR(last[1].get<double>(), 3.0, 1e-9);
  EXPECT_EQ(sheet->etag, service.GetSurface(id)->etag);

  auto svg = service.GetSurfaceSvg(id);
  ASSERT_TRUE(svg.ok());
  EXPECT_EQ(svg->body.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg->body.find("</svg>"), std::string::npos);
  EXPECT_EQ(std::count(svg->body.begin(), svg->body.end(), '\n') > 49, true);  // 49 cells
}

TEST(Service, DeformsInlineAndById) {
  Service service({});
  const std::string plate = PlateObj();
  auto inline_reply = service.Deform(
      {plate, std::string(R"({"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},
          "sampling":{"nu":8,"nv":8},"output":{"format":"obj"}})"),
       ""});
  ASSERT_TRUE(inline_reply.ok()) << inline_reply.status().ToString();
  EXPECT_EQ(inline_reply->content_type, "model/obj");
  const json stats = StatsOf(*inline_reply);
  // Adaptive subdivision by default: the plate's large faces follow the cylinder.
  EXPECT_EQ(stats.at("subdivision").at("mode"), "adaptive");
  EXPECT_EQ(stats.at("subdivision").at("vertices_before"), 8);
  EXPECT_EQ(stats.at("subdivision").at("triangles_before"), 12);
  EXPECT_GT(stats.at("vertices"), 8);
  EXPECT_EQ(stats.at("vertices"), stats.at("subdivision").at("vertices_after"));
  EXPECT_EQ(stats.at("triangles"), stats.at("subdivision").at("triangles_after"));
  EXPECT_LE(stats.at("subdivision").at("max_deviation").get<double>(),
            stats.at("subdivision").at("tolerance").get<double>());
  const std::string id = stats.at("surface_id");

  // Subdivision off keeps the input's vertices and faces.
  auto off = service.Deform(
      {plate,
       R"({"surface_id":")" + id + R"(","subdivision":{"mode":"off"},"output":{"format":"obj"}})",
       ""});
  ASSERT_TRUE(off.ok()) << off.status().ToString();
  EXPECT_EQ(StatsOf(*off).at("vertices"), 8);
  EXPECT_EQ(StatsOf(*off).at("triangles"), 12);

  // Same surface by id: the same bytes.
  auto by_id =
      service.Deform({plate, R"({"surface_id":")" + id + R"(","output":{"format":"obj"}})", ""});
  ASSERT_TRUE(by_id.ok()) << by_id.status().ToString();
  EXPECT_TRUE(by_id->cache_hit);
  EXPECT_EQ(by_id->body, inline_reply->body);
  EXPECT_EQ(by_id->etag, inline_reply->etag);

  // Every vertex lands at radius 2 +- half the thickness (anchor: center).
  auto back = ImportMesh(by_id->body);
  ASSERT_TRUE(back.ok());
  for (const Vec3& p : back->mesh.positions) {
    EXPECT_NEAR(p.head<2>().norm(), 2.0, 0.025 + 1e-6);
  }
  // Accept picks the format when the parameters do not.
  auto glb = service.Deform({plate, R"({"surface_id":")" + id + R"("})", "model/gltf-binary"});
  ASSERT_TRUE(glb.ok());
  EXPECT_EQ(glb->body.substr(0, 4), "glTF");
}

// A model that comes back reuses its placement (the fit), and only the same
// model on the same surface with the same placement options does; the bytes
// are those of a service that computed it afresh.
TEST(Service, ReusesThePlacementOfAModelThatComesBack) {
  Service service(EveryAnswerMade());
  const std::string plate = PlateObj();
  const auto created = service.CreateSurface(kCylinder);
  ASSERT_TRUE(created.ok());
  const std::string id = json::parse(created->body).at("id");
  auto deform = [&](Service& s, const std::string& mesh, const std::string& placement,
                    const std::string& format) {
    auto r = s.Deform({mesh,
                       R"({"surface_id":")" + id + R"(","placement":)" + placement +
                           R"(,"output":{"format":")" + format + R"("}})",
                       ""});
    EXPECT_TRUE(r.ok()) << r.status().ToString();
    return r;
  };
  auto reused = [](const Result<Reply>& r) {
    return StatsOf(*r).at("placement").at("reused").get<bool>();
  };
  const std::string fit = R"({"scale":"fit"})";
  auto first = deform(service, plate, fit, "obj");
  EXPECT_FALSE(reused(first));
  auto again = deform(service, plate, fit, "obj");
  EXPECT_TRUE(reused(again));
  EXPECT_EQ(again->body, first->body);
  // Another output format: the same placement.
  auto as_ply = deform(service, plate, fit, "ply");
  EXPECT_TRUE(reused(as_ply));
  Service fresh({});
  ASSERT_TRUE(fresh.CreateSurface(kCylinder).ok());
  auto computed = deform(fresh, plate, fit, "ply");
  EXPECT_FALSE(reused(computed));
  EXPECT_EQ(as_ply->body, computed->body);

  // Other options, or a model with one vertex moved: placed afresh.
  EXPECT_FALSE(reused(deform(service, plate, R"({"scale":"fit","rotation_deg":30})", "obj")));
  Mesh moved = testing::ThinPlate(1.0, 0.5, 0.05);
  moved.positions[0].x() -= 0.125;
  auto moved_obj = ExportMesh(moved, MeshFormat::kObj);
  ASSERT_TRUE(moved_obj.ok());
  EXPECT_FALSE(reused(deform(service, *moved_obj, fit, "obj")));
  const PlacementMemoStats stats = service.placement_memo_stats();
  EXPECT_EQ(stats.hits, 2u);
  EXPECT_EQ(stats.misses, 3u);
  EXPECT_EQ(stats.entries, 3u);
}

// A model that comes back also reuses where its vertices lie on the sheet
// (the footprint), with and without subdivision, with and without normals:
// the bytes are those of a service that located them afresh. A service
// without a footprint budget keeps none.
TEST(Service, ReusesWhereTheVerticesOfAModelThatComesBackLie) {
  // A saddle (a sheet of cells: the cylinder above unrolls in closed form).
  const std::string saddle =
      R"({"surface":{"kind":"bezier","degree_u":2,"degree_v":2,"control_points":)"
      R"([[0,0,0],[2,0,1],[4,0,0],[0,2,1],[2,2,0],[4,2,1],[0,4,0],[2,4,1],[4,4,0]]},)"
      R"("sampling":{"nu":12,"nv":12}})";
  const Mesh grid = testing::FlatGrid(-1, -1, 2, 2, 24, 24, 0.1);
  Mesh bare = grid;
  bare.normals.clear();
  bare.tangents.clear();
  auto obj = [](const Mesh& m) {
    auto bytes = ExportMesh(m, MeshFormat::kObj);
    EXPECT_TRUE(bytes.ok());
    return bytes.ok() ? *bytes : std::string();
  };
  ServiceOptions no_budget;
  no_budget.limits.footprint_memo_bytes = 0;
  Service service({}), fresh({}), without(no_budget);
  std::string id;
  for (Service* s : {&service, &fresh, &without}) {
    auto created = s->CreateSurface(saddle);
    ASSERT_TRUE(created.ok()) << created.status().ToString();
    id = created->surface_id;
  }
  auto deform = [&](Service& s, const std::string& mesh, const char* subdivision) {
    auto r = s.Deform({mesh,
                       R"({"surface_id":")" + id +
                           R"(","placement":{"scale":"fit"},"subdivision":{"mode":")" +
                           subdivision + R"("},"output":{"format":"ply"}})",
                       ""});
    EXPECT_TRUE(r.ok()) << r.status().ToString();
    return r.ok() ? r->body : std::string();
  };
  // The two models share their positions, so they share one entry.
  for (const std::string& mesh : {obj(grid), obj(bare)}) {
    for (const char* subdivision : {"off", "adaptive", "uniform"}) {
      const std::string first = deform(service, mesh, subdivision);
      EXPECT_EQ(service.placement_memo_stats().footprints, 1u);
      EXPECT_EQ(deform(service, mesh, subdivision), first) << subdivision;
      EXPECT_EQ(deform(fresh, mesh, subdivision), first) << subdivision;
      EXPECT_EQ(deform(without, mesh, subdivision), first) << subdivision;
    }
  }
  const PlacementMemoStats stats = service.placement_memo_stats();
  EXPECT_EQ(stats.entries, 1u);
  EXPECT_EQ(stats.footprint_bytes, 625 * sizeof(SheetLocation));
  EXPECT_EQ(without.placement_memo_stats().footprints, 0u);
}

// An adaptive subdivision that added nothing to a model is not run when the
// same model comes back with the same subdivision options: the bytes are
// those of a service that ran it. Other options, other triangles (the same
// positions) or a subdivision that refined run it.
TEST(Service, SkipsASubdivisionThatAddedNothingToAModelThatComesBack) {
  const std::string saddle =
      R"({"surface":{"kind":"bezier","degree_u":2,"degree_v":2,"control_points":)"
      R"([[0,0,0],[2,0,1],[4,0,0],[0,2,1],[2,2,0],[4,2,1],[0,4,0],[2,4,1],[4,4,0]]},)"
      R"("sampling":{"nu":12,"nv":12}})";
  Service service(EveryAnswerMade()), fresh(EveryAnswerMade());
  std::string id;
  for (Service* s : {&service, &fresh}) {
    auto created = s->CreateSurface(saddle);
    ASSERT_TRUE(created.ok()) << created.status().ToString();
    id = created->surface_id;
  }
  auto obj = [](const Mesh& m) {
    auto bytes = ExportMesh(m, MeshFormat::kObj);
    EXPECT_TRUE(bytes.ok());
    return bytes.ok() ? *bytes : std::string();
  };
  struct Deformed {
    std::string body;
    json subdivision;
  };
  auto deform = [&](Service& s, const std::string& mesh, const std::string& subdivision) {
    auto r =
        s.Deform({mesh,
                  R"({"surface_id":")" + id + R"(","placement":{"scale":"fit"},"subdivision":)" +
                      subdivision + R"(,"output":{"format":"ply"}})",
                  ""});
    EXPECT_TRUE(r.ok()) << r.status().ToString();
    if (!r.ok()) return Deformed{};
    return Deformed{r->body, StatsOf(*r).at("subdivision")};
  };
  const Mesh fine = testing::FlatGrid(-1, -1, 2, 2, 80, 80, 0.02);
  const std::string adaptive = R"({"mode":"adaptive"})";
  const Deformed first = deform(service, obj(fine), adaptive);
  ASSERT_EQ(first.subdivision.at("vertices_added"), 0) << "the test needs a model left as it is";
  EXPECT_FALSE(first.subdivision.at("reused").get<bool>());
  EXPECT_GT(first.subdivision.at("max_estimated_deviation").get<double>(), 0.0);

  const Deformed again = deform(service, obj(fine), adaptive);
  EXPECT_TRUE(again.subdivision.at("reused").get<bool>());
  EXPECT_EQ(again.body, first.body);
  EXPECT_EQ(again.subdivision.at("max_estimated_deviation"),
            first.subdivision.at("max_estimated_deviation"));
  EXPECT_EQ(deform(fresh, obj(fine), adaptive).body, first.body);
  EXPECT_EQ(service.placement_memo_stats().subdivisions_skipped, 1u);

  // A tolerance below the deviation (~3e-4): run again, and it refines.
  const std::string tighter = R"({"mode":"adaptive","tolerance":1e-4})";
  const Deformed tight = deform(service, obj(fine), tighter);
  EXPECT_FALSE(tight.subdivision.at("reused").get<bool>());
  EXPECT_GT(tight.subdivision.at("vertices_added").get<size_t>(), 0u);
  EXPECT_EQ(deform(service, obj(fine), tighter).body, tight.body);
  // The same positions with every triangle's winding reversed: other
  // triangles (the positions, and so the placement, are shared).
  Mesh flipped = fine;
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  const Deformed other = deform(service, obj(flipped), adaptive);
  EXPECT_FALSE(other.subdivision.at("reused").get<bool>());
  EXPECT_EQ(other.body, deform(fresh, obj(flipped), adaptive).body);
  // The verdict of the original options was replaced by the last one.
  EXPECT_TRUE(deform(service, obj(flipped), adaptive).subdivision.at("reused").get<bool>());
  EXPECT_FALSE(deform(service, obj(fine), adaptive).subdivision.at("reused").get<bool>());
  EXPECT_EQ(service.placement_memo_stats().subdivisions_skipped, 2u);
}

// Requests for one model at once: the first to finish stores the footprint,
// the others store theirs or find it; every response is the same.
TEST(Service, ConcurrentRequestsForOneModelShareItsFootprint) {
  Service service(EveryAnswerMade());
  auto created =
      service.CreateSurface(R"({"surface":{"kind":"wave"},"sampling":{"nu":12,"nv":12}})");
  ASSERT_TRUE(created.ok()) << created.status().ToString();
  auto mesh = ExportMesh(testing::FlatGrid(-1, -0.5, 2, 1, 30, 15, 0.05), MeshFormat::kPly);
  ASSERT_TRUE(mesh.ok());
  const std::string params = R"({"surface_id":")" + created->surface_id +
                             R"(","placement":{"scale":"fit"},"output":{"format":"ply"}})";
  constexpr int kThreads = 4, kEach = 3;
  std::vector<std::string> bodies(kThreads * kEach);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int k = 0; k < kEach; ++k) {
        auto r = service.Deform({*mesh, params, ""});
        if (r.ok()) bodies[t * kEach + k] = r->body;
      }
    });
  }
  for (auto& t : threads) t.join();
  ASSERT_FALSE(bodies[0].empty());
  for (const std::string& b : bodies) EXPECT_EQ(b, bodies[0]);
  const PlacementMemoStats stats = service.placement_memo_stats();
  EXPECT_EQ(stats.entries, 1u);
  EXPECT_EQ(stats.footprints, 1u);
  EXPECT_EQ(stats.hits + stats.misses, static_cast<uint64_t>(kThreads * kEach));
}

// placement.up "auto" (the API's default): a Y-up glTF figure stands up on a
// plane, the same figure as OBJ lies as +Z would have it, a plate thin in X
// stands on its thin axis; explicit axes are kept. The stats say which.
TEST(Service, UpAutoStandsGltfModelsUpAndThinObjectsOnTheirFace) {
  Service service(ServiceOptions{});
  // A plane: [0, 4]^2 at z = 0 (output z is the height along the normal).
  const std::string plane =
      R"({"surface":{"kind":"bezier","degree_u":1,"degree_v":1,)"
      R"("control_points":[[0,0,0],[4,0,0],[0,4,0],[4,4,0]]},"sampling":{"nu":4,"nv":4}})";
  auto created = service.CreateSurface(plane);
  ASSERT_TRUE(created.ok()) << created.status().ToString();
  const std::string id = created->surface_id;
  // A figure 0.2 wide, 1.0 tall along +Y, 0.3 deep.
  Mesh figure = testing::ThinPlate(0.2, 1.0, 0.3);
  ExportOptions plain;
  plain.glb = GlbEncoding::kPlain;
  const std::string glb = *ExportMesh(figure, MeshFormat::kGlb, plain);
  const std::string obj = *ExportMesh(figure, MeshFormat::kObj);
  auto extent_z = [](const std::string& body) {
    auto m = ImportMesh(body);
    EXPECT_TRUE(m.ok());
    double lo = 1e300, hi = -1e300;
    for (const Vec3& p : m->mesh.positions) {
      lo = std::min(lo, p.z());
      hi = std::max(hi, p.z());
    }
    return hi - lo;
  };
  auto deform = [&](const std::string& mesh, const std::string& placement) {
    auto r = service.Deform({mesh,
                             R"({"surface_id":")" + id + R"(","placement":)" + placement +
                                 R"(,"subdivision":{"mode":"off"},"output":{"format":"obj"}})",
                             ""});
    EXPECT_TRUE(r.ok()) << r.status().ToString();
    return r.ok() ? *r : Reply{};
  };
  const Reply standing = deform(glb, "{}");
  json st = StatsOf(standing).at("placement");
  EXPECT_EQ(st.at("up"), "+y");
  EXPECT_EQ(st.at("up_reason"), "gltf");
  EXPECT_NEAR(extent_z(standing.body), 1.0, 1e-6);  // its height along the normal
  const Reply lying = deform(glb, R"({"up":"+z"})");
  st = StatsOf(lying).at("placement");
  EXPECT_EQ(st.at("up"), "+z");
  EXPECT_EQ(st.at("up_reason"), "given");
  EXPECT_NEAR(extent_z(lying.body), 0.3, 1e-6);
  const Reply as_obj = deform(obj, "{}");
  st = StatsOf(as_obj).at("placement");
  EXPECT_EQ(st.at("up"), "+z");  // 0.2 is not at most half of 0.3: not clearly thinnest
  EXPECT_EQ(st.at("up_reason"), "default");
  // A plate thin along X (a logo standing on its edge in the file).
  const std::string logo = *ExportMesh(testing::ThinPlate(0.02, 0.8, 0.5), MeshFormat::kObj);
  const Reply flat = deform(logo, "{}");
  st = StatsOf(flat).at("placement");
  EXPECT_EQ(st.at("up"), "+x");
  EXPECT_EQ(st.at("up_reason"), "thinnest");
  EXPECT_NEAR(extent_z(flat.body), 0.02, 1e-6);
}

// X-Surfdeform-Surface-Id (or ?surface_id=), which load balancers route by:
// the surface when the parameters name none, else it must agree with them.
TEST(Service, TheRoutingSurfaceIdNamesTheSurfaceOrMustAgree) {
  Service service({});
  auto created = service.CreateSurface(kCylinder);
  ASSERT_TRUE(created.ok());
  const std::string id = json::parse(created->body).at("id");
  const std::string plate = PlateObj();
  const std::string obj = R"({"output":{"format":"obj"}})";
  auto by_header = service.Deform({plate, obj, "", id});
  ASSERT_TRUE(by_header.ok()) << by_header.status().ToString();
  auto by_params =
      service.Deform({plate, R"({"surface_id":")" + id + R"(","output":{"format":"obj"}})", ""});
  ASSERT_TRUE(by_params.ok());
  EXPECT_EQ(by_header->body, by_params->body);
  // Inline, the header must be that surface's id.
  auto inline_agrees = service.Deform(
      {plate, R"({"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},
          "sampling":{"nu":8,"nv":8}})",
       "", id});
  EXPECT_TRUE(inline_agrees.ok()) << inline_agrees.status().ToString();
  const std::string other(32, 'a');
  for (const std::string& params :
       {R"({"surface_id":")" + id + R"("})",
        std::string(R"({"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180},
          "sampling":{"nu":8,"nv":8}})")}) {
    auto disagrees = service.Deform({plate, params, "", other});
    ASSERT_FALSE(disagrees.ok());
    EXPECT_EQ(disagrees.status().code(), ErrorCode::kMalformed);
    EXPECT_EQ(disagrees.status().field(), "X-Surfdeform-Surface-Id");
    EXPECT_NE(disagrees.status().message().find(other), std::string::npos);
    EXPECT_NE(disagrees.status().message().find(id), std::string::npos);
  }
}

TEST(Service, ErrorsSayWhatAndWhere) {
  ServiceOptions options;
  options.limits.max_grid_side = 32;
  options.limits.max_vertices = 4;
  Service service(options);
  auto r = service.CreateSurface(R"({"surface":{"kind":"cylinder"},"sampling":{"nu":8,"nv":64}})");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(r.status().field(), "sampling.nv");
  EXPECT_EQ(r.status().limit(), 32);
  EXPECT_EQ(r.status().actual(), 64);

  r = service.CreateSurface(R"({"surface":{"kind":"cylinder","radius":0}})");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().field(), "surface.radius");

  EXPECT_EQ(service.GetSurface("0123456789abcdef0123456789abcdef").status().code(),
            ErrorCode::kNotFound);
  EXPECT_EQ(service.GetSurface("../etc/passwd").status().code(), ErrorCode::kNotFound);

  const std::string plate = PlateObj();
  r = service.Deform({plate, R"({"surface":{"kind":"cylinder"}})", ""});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kLimitExceeded);  // 8 vertices, limit 4
  EXPECT_EQ(r.status().limit(), 4);
  EXPECT_GT(r.status().actual(), 4);

  ServiceOptions hurried;
  hurried.limits.flatten_time_budget_ms = 30;
  Service slow(hurried);
  r = slow.CreateSurface(
      R"({"surface":{"kind":"wave"},"sampling":{"nu":64,"nv":64},"flatten":{"method":"paper"}})");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kDeadlineExceeded);
  EXPECT_EQ(r.status().field(), "flatten");
  EXPECT_EQ(r.status().limit(), 30);
  EXPECT_GT(r.status().actual(), 30);
  EXPECT_EQ(slow.cache_stats().entries, 0u);

  Service roomy({});
  r = roomy.Deform({plate, R"({"surface":{"kind":"cylinder"},"placement":{"scale":100}})", ""});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kOutsideSheet);
  r = roomy.Deform({std::string("not a mesh at all"), R"({"surface":{"kind":"cylinder"}})", ""});
  EXPECT_EQ(r.status().code(), ErrorCode::kUnsupportedFormat);
  r = roomy.Deform({plate, R"({"surface":{"kind":"cylinder"}})", "image/png"});
  EXPECT_EQ(r.status().code(), ErrorCode::kNotAcceptable);
  r = roomy.Deform({plate, R"({"surface":{"kind":"cylinder"},"placement":{"up":"z"}})", ""});
  EXPECT_EQ(r.status().field(), "placement.up");
}

TEST(Service, ConcurrentIdenticalRequestsFlattenOnce) {
  ServiceOptions options;
  options.limits.max_in_flight = 16;
  Service service(options);
  const char* body =
      R"({"surface":{"kind":"bezier","degree_u":2,"degree_v":2,"control_points":[[0,0,0],[1,0,0.5],[2,0,0],
        [0,1,0.3],[1,1,1],[2,1,0.3],[0,2,0],[1,2,0.5],[2,2,0]]},"sampling":{"nu":24,"nv":24}})";
  std::vector<std::string> etags(8);
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      auto r = service.CreateSurface(body);
      if (r.ok()) etags[t] = json::parse(r->body).at("id");
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(service.cache_stats().misses, 1u);
  for (int t = 1; t < 8; ++t) EXPECT_EQ(etags[t], etags[0]);
  EXPECT_FALSE(etags[0].empty());
}

// Checklist 27: requests that only wait on a flattening already in flight for
// the same surface, or hit the cache, are not refused by the work-in-flight
// limit. With room for one flattening, sixteen identical requests on a cold
// cache all succeed on one flattening (they used to take a ticket each: all
// but the first were refused while it ran).
TEST(ServiceAdmission, IdenticalRequestsWaitOnOneFlatteningInsteadOfBeingRefused) {
  ServiceOptions options;
  options.limits.max_in_flight = 1;
  options.limits.max_queued = 0;  // refused at once
  // Room for the sanitizer build, which runs the flattening ~15x slower.
  options.limits.flatten_time_budget_ms = options.limits.request_time_budget_ms = 120000;
  Service service(options);
  // The paper's gradient descent on a 28 x 28 wave: long enough (~0.2 s in a
  // release build) for all sixteen to arrive while it runs.
  const std::string body =
      R"({"surface":{"kind":"wave"},"sampling":{"nu":28,"nv":28},"flatten":{"method":"paper"}})";
  constexpr int kClients = 16;
  std::vector<int> failures(kClients, 0);
  std::vector<char> computed(kClients, 0);
  std::atomic<bool> go{false};
  std::vector<std::thread> threads;
  for (int t = 0; t < kClients; ++t) {
    threads.emplace_back([&, t] {
      while (!go) std::this_thread::yield();
      auto r = service.CreateSurface(body);
      failures[t] = r.ok() ? 0 : static_cast<int>(r.status().code());
      computed[t] = r.ok() && !r->cache_hit;
    });
  }
  go = true;
  for (auto& t : threads) t.join();
  for (int t = 0; t < kClients; ++t) EXPECT_EQ(failures[t], 0) << "client " << t;
  EXPECT_EQ(service.cache_stats().misses, 1u);
  int flattenings = 0;
  for (char c : computed) flattenings += c;
  EXPECT_EQ(flattenings, 1);
}

// A cached surface is served while the limit is full; a new surface is not.
TEST(ServiceAdmission, ACacheHitIsServedWhileTheLimitIsFull) {
  ServiceOptions options;
  options.limits.max_in_flight = 1;
  options.limits.max_queued = 0;  // refused at once
  options.limits.flatten_time_budget_ms = options.limits.request_time_budget_ms = 120000;
  Service service(options);
  const std::string cached = R"({"surface":{"kind":"cylinder"},"sampling":{"nu":8,"nv":8}})";
  ASSERT_TRUE(service.CreateSurface(cached).ok());
  std::thread slow([&] {  // holds the only slot for a while (~0.2 s in a release build)
    Result<Reply> r = Status(ErrorCode::kUnavailable, "not tried");
    for (int k = 0; k < 400 && !r.ok(); ++k) {  // until it gets the slot
      r = service.CreateSurface(
          R"({"surface":{"kind":"wave"},"sampling":{"nu":28,"nv":28},"flatten":{"method":"paper"}})");
      if (!r.ok()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_TRUE(r.ok()) << r.status().ToString();
  });
  // Wait until the slot is taken: a new surface (a new one each time, so none
  // is a cache hit) is refused then.
  bool refused = false;
  for (int k = 0; k < 400 && !refused; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    auto r =
        service.CreateSurface(R"({"surface":{"kind":"cone","radius_bottom":)" +
                              std::to_string(1.0 + 0.001 * k) + R"(},"sampling":{"nu":8,"nv":8}})");
    refused = !r.ok() && r.status().code() == ErrorCode::kUnavailable;
  }
  EXPECT_TRUE(refused) << "the slow flattening never held the slot";
  auto hit = service.CreateSurface(cached);
  EXPECT_TRUE(hit.ok()) << hit.status().ToString();  // no ASSERT: `slow` must be joined
  EXPECT_TRUE(hit.ok() && hit->cache_hit);
  slow.join();
}

// Kept answers.

// A surface id and the request of a plate on it, by id, in `output`.
struct PlateAnswer {
  std::string surface_id;
  std::string params(const std::string& output, double scale = 1.0) const {
    return R"({"surface_id":")" + surface_id + R"(","placement":{"scale":)" +
           std::to_string(scale) + R"(},"output":)" + output + "}";
  }
};

PlateAnswer PlateOn(Service& service) {
  auto created = service.CreateSurface(kCylinder);
  EXPECT_TRUE(created.ok());
  return {created.ok() ? json::parse(created->body).at("id").get<std::string>() : ""};
}

TEST(Service, KeepsAnswersAndServesThemByteForByteWithoutWork) {
  Service service({});
  const PlateAnswer plate = PlateOn(service);
  const std::string mesh = PlateObj();
  for (const char* output : {R"({"format":"drc"})", R"({"compression":"meshopt"})",
                             R"({"format":"ply","distortion":true})"}) {
    SCOPED_TRACE(output);
    const CacheStats before = service.answer_cache_stats();
    auto made = service.Deform({mesh, plate.params(output), ""});
    ASSERT_TRUE(made.ok()) << made.status().ToString();
    EXPECT_FALSE(StatsOf(*made).contains("answer_kept"));
    auto kept = service.Deform({mesh, plate.params(output), ""});
    ASSERT_TRUE(kept.ok());
    EXPECT_EQ(kept->body, made->body);
    EXPECT_EQ(kept->etag, made->etag);
    EXPECT_EQ(kept->content_type, made->content_type);
    EXPECT_TRUE(StatsOf(*kept).value("answer_kept", false));
    EXPECT_TRUE(kept->timings.empty()) << "no parse, deformation or encoding";
    const CacheStats after = service.answer_cache_stats();
    EXPECT_EQ(after.misses - before.misses, 1u);
    EXPECT_EQ(after.hits - before.hits, 1u);
  }
  // The same model by id: the same key, so the same answer (kept).
  auto uploaded = service.UploadModel(mesh, "");
  ASSERT_TRUE(uploaded.ok());
  const std::string by_id = R"({"model_id":")" + uploaded->model_id + R"(",)" +
                            plate.params(R"({"format":"drc"})").substr(1);
  auto kept = service.Deform({"", by_id, ""});
  ASSERT_TRUE(kept.ok()) << kept.status().ToString();
  EXPECT_TRUE(StatsOf(*kept).value("answer_kept", false));
}

TEST(Service, AnIfNoneMatchNamingTheAnswerIs304BeforeAnyWork) {
  Service service({});
  const PlateAnswer plate = PlateOn(service);
  auto uploaded = service.UploadModel(PlateObj(), "");
  ASSERT_TRUE(uploaded.ok());
  const std::string params = R"({"model_id":")" + uploaded->model_id + R"(",)" +
                             plate.params(R"({"compression":"meshopt"})").substr(1);
  auto made = service.Deform({"", params, ""});
  ASSERT_TRUE(made.ok()) << made.status().ToString();
  const CacheStats models = service.model_cache_stats();
  const CacheStats answers = service.answer_cache_stats();
  DeformRequest again{"", params, ""};
  again.if_none_match = "\"" + made->etag + "\"";
  auto not_modified = service.Deform(again);
  ASSERT_TRUE(not_modified.ok());
  EXPECT_TRUE(not_modified->not_modified);
  EXPECT_TRUE(not_modified->body.empty());
  EXPECT_EQ(not_modified->etag, made->etag);
  // Neither the model nor the kept answers were looked at.
  EXPECT_EQ(service.model_cache_stats().hits, models.hits);
  EXPECT_EQ(service.answer_cache_stats().hits, answers.hits);
  EXPECT_EQ(service.answer_cache_stats().misses, answers.misses);
  // Another placement's ETag differs: made.
  const std::string moved_params = R"({"model_id":")" + uploaded->model_id + R"(",)" +
                                   plate.params(R"({"compression":"meshopt"})", 0.5).substr(1);
  DeformRequest other{"", moved_params, ""};
  other.if_none_match = again.if_none_match;
  auto moved = service.Deform(other);
  ASSERT_TRUE(moved.ok()) << moved.status().ToString();
  EXPECT_FALSE(moved->not_modified);
  EXPECT_NE(moved->etag, made->etag);
}

TEST(Service, KeepsAnimationsAndAnswers304BeforeAnyWork) {
  Service service({});
  auto uploaded = service.UploadModel(PlateObj(), "");
  ASSERT_TRUE(uploaded.ok());
  auto params = [&](double scale) {
    return R"({"model_id":")" + uploaded->model_id +
           R"(","animation":{"keyframes":[)"
           R"({"time":0,"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180}},)"
           R"({"time":1,"surface":{"kind":"cylinder","radius":3,"height":3,"angle_deg":180}}],)"
           R"("frames":3},"sampling":{"nu":8,"nv":8},"placement":{"scale":)" +
           std::to_string(scale) + "}}";
  };
  auto made = service.Animate({"", params(1.0), ""});
  ASSERT_TRUE(made.ok()) << made.status().ToString();
  EXPECT_FALSE(StatsOf(*made).contains("answer_kept"));
  const CacheStats before = service.answer_cache_stats();
  auto kept = service.Animate({"", params(1.0), ""});
  ASSERT_TRUE(kept.ok()) << kept.status().ToString();
  EXPECT_EQ(kept->body, made->body);
  EXPECT_EQ(kept->etag, made->etag);
  EXPECT_TRUE(StatsOf(*kept).value("answer_kept", false));
  EXPECT_TRUE(kept->timings.empty()) << "no flattening, deformation or encoding";
  EXPECT_EQ(service.answer_cache_stats().hits - before.hits, 1u);
  // If-None-Match naming it: 304, with neither the model nor the answers
  // looked at.
  const std::string same = params(1.0), smaller = params(0.5);  // the requests view them
  DeformRequest again{"", same, ""};
  again.if_none_match = "\"" + made->etag + "\"";
  const CacheStats models = service.model_cache_stats();
  const CacheStats answers = service.answer_cache_stats();
  auto not_modified = service.Animate(again);
  ASSERT_TRUE(not_modified.ok());
  EXPECT_TRUE(not_modified->not_modified);
  EXPECT_EQ(service.model_cache_stats().hits, models.hits);
  EXPECT_EQ(service.answer_cache_stats().hits, answers.hits);
  // Another placement is another answer.
  DeformRequest other{"", smaller, ""};
  other.if_none_match = again.if_none_match;
  auto moved = service.Animate(other);
  ASSERT_TRUE(moved.ok()) << moved.status().ToString();
  EXPECT_FALSE(moved->not_modified);
  EXPECT_NE(moved->etag, made->etag);
  EXPECT_NE(moved->body, made->body);
  // One frame of it through POST /v1/deform: kept too, per frame.
  const std::string frame1 = same.substr(0, same.size() - 1) + R"(,"frame":1})";
  const std::string frame2 = same.substr(0, same.size() - 1) + R"(,"frame":2})";
  auto first = service.Deform({"", frame1, ""});
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  auto again_frame = service.Deform({"", frame1, ""});
  ASSERT_TRUE(again_frame.ok());
  EXPECT_EQ(again_frame->body, first->body);
  EXPECT_TRUE(StatsOf(*again_frame).value("answer_kept", false));
  auto other_frame = service.Deform({"", frame2, ""});
  ASSERT_TRUE(other_frame.ok());
  EXPECT_FALSE(StatsOf(*other_frame).contains("answer_kept"));
  EXPECT_NE(other_frame->etag, first->etag);
}

TEST(Service, AnimatesSurfacesThatCloseOpenOrChangeTheirSector) {
  // A can that opens, a whole cone whose sector changes (so the frames'
  // sheets allow different extensions past the seam): every frame shares
  // one grid and the plate goes through them all.
  Service service({});
  const std::string mesh = PlateObj();
  for (const char* keys :
       {R"({"time":0,"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":360}},)"
        R"({"time":1,"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":300}})",
        R"({"time":0,"surface":{"kind":"cone","radius_bottom":2,"radius_top":1,"height":2,)"
        R"("angle_deg":360}},{"time":1,"surface":{"kind":"cone","radius_bottom":2,)"
        R"("radius_top":0.2,"height":0.5,"angle_deg":360}})"}) {
    SCOPED_TRACE(keys);
    const std::string params = std::string(R"({"animation":{"keyframes":[)") + keys +
                               R"(],"frames":4},"sampling":{"nu":9,"nv":5}})";
    auto r = service.Animate({mesh, params, ""});
    EXPECT_TRUE(r.ok()) << r.status().ToString();
  }
}

TEST(Service, AnAnswerMadeAgainAfterItsEvictionIsByteIdentical) {
  const std::string mesh = PlateObj();
  // A budget that holds one of these answers, not two.
  size_t one = 0;
  {
    Service probe({});
    auto r = probe.Deform({mesh, PlateOn(probe).params(R"({"format":"glb"})"), ""});
    ASSERT_TRUE(r.ok());
    one = EstimateBytes(*r);
  }
  ServiceOptions o;
  o.limits.answer_cache_bytes = one * 3 / 2;
  Service service(o);
  const PlateAnswer plate = PlateOn(service);
  auto first = service.Deform({mesh, plate.params(R"({"format":"glb"})"), ""});
  auto other = service.Deform({mesh, plate.params(R"({"format":"glb"})", 0.5), ""});
  auto again = service.Deform({mesh, plate.params(R"({"format":"glb"})"), ""});
  ASSERT_TRUE(first.ok() && other.ok() && again.ok());
  EXPECT_GE(service.answer_cache_stats().evictions, 1u);
  EXPECT_FALSE(StatsOf(*again).contains("answer_kept")) << "made again";
  EXPECT_EQ(again->body, first->body);
  EXPECT_EQ(again->etag, first->etag);
}

TEST(Service, ABudgetOfZeroKeepsNoAnswer) {
  Service service(EveryAnswerMade());
  const PlateAnswer plate = PlateOn(service);
  const std::string mesh = PlateObj();
  for (int k = 0; k < 2; ++k) {
    auto r = service.Deform({mesh, plate.params(R"({"format":"drc"})"), ""});
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(StatsOf(*r).contains("answer_kept"));
  }
  const CacheStats s = service.answer_cache_stats();
  EXPECT_EQ(s.hits + s.misses + s.entries, 0u);
  EXPECT_EQ(s.capacity_bytes, 0u);
}

// Every committed seed of the request-cost fuzzer (tests/fuzz/seeds/estimate:
// parameters on the first line, a small mesh after; extreme centres,
// scales, tolerances) answered by a service set up as the fuzzer's, here in
// the unit tests too: the sanitized build aborts on undefined behaviour
// (CI once found a centre at (0, 1e20) converting 1.2e21 to an int).
// Each is answered: a result, or an error that names its field.
TEST(HostileInput, EveryEstimateSeedIsAnsweredWithoutUndefinedBehaviour) {
  Service service(EstimateServiceOptions(1000));
  int seeds = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(SURFDEFORM_FUZZ_SEEDS_DIR) + "/estimate")) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string input((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    DeformRequest request;  // views of `input`
    ASSERT_TRUE(EstimateRequest(input, &request)) << entry.path();
    auto reply = service.Deform(request);
    if (!reply.ok()) {
      EXPECT_FALSE(reply.status().message().empty()) << entry.path();
    } else {
      EXPECT_FALSE(reply->body.empty()) << entry.path();
    }
    ++seeds;
  }
  EXPECT_GE(seeds, 12);
}

}  // namespace
}  // namespace surfdeform
