// The surface store alone, without the service: both levels (the second one
// on a real redis-server), single flight, admission of the flattening only,
// eviction, animations.
#include "service/surface_store.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "engine/flatten/mesh_flatten.hpp"
#include "proto/api.hpp"
#include "service/sheet_codec.hpp"
#include "support/redis_process.hpp"
#include "support/surface_file.hpp"

namespace surfdeform {
namespace {

using nlohmann::json;

proto::SurfaceRequest Cylinder(double radius, int n = 8) {
  auto r = proto::ParseSurfaceRequest(json{
      {"surface", {{"kind", "cylinder"}, {"radius", radius}, {"height", 3}, {"angle_deg", 180}}},
      {"sampling", {{"nu", n}, {"nv", n}}}});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return *r;
}

proto::AnimationRequest Swim(int frames) {
  auto r = proto::ParseAnimateParams(
      json::parse(R"({"animation":{"frames":)" + std::to_string(frames) + R"(,"fps":10,
      "keyframes":[
        {"time":0,"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":90}},
        {"time":1,"surface":{"kind":"cylinder","radius":2,"height":3,"angle_deg":180}}]},
      "sampling":{"nu":8,"nv":8}})"));
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r->animation;
}

ServiceLimits Limits() {
  ServiceLimits l;
  l.flatten_time_budget_ms = l.request_time_budget_ms = 120000;  // sanitizer builds
  return l;
}

TEST(SurfaceStore, FlattensOnceAndFindsByIdAfter) {
  SurfaceStore store(Limits(), 1, nullptr);
  const RequestClock clock(60000);
  bool hit = true;
  auto first = store.Flattened(Cylinder(2), clock, &hit);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  EXPECT_FALSE(hit);
  EXPECT_EQ((*first)->id, proto::SurfaceId(Cylinder(2)));
  EXPECT_EQ((*first)->sheet.flat.size(), 64u);
  EXPECT_GT((*first)->bytes, 64u * 64);

  auto again = store.Flattened(Cylinder(2), clock, &hit);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(hit);
  EXPECT_EQ(again->get(), first->get());  // the one entry, shared

  auto found = store.Find((*first)->id);
  ASSERT_TRUE(found.ok());
  EXPECT_EQ(found->get(), first->get());
  const CacheStats stats = store.surface_stats();
  EXPECT_EQ(stats.misses, 1u);
  EXPECT_EQ(stats.hits, 2u);
  EXPECT_EQ(stats.entries, 1u);
}

TEST(SurfaceStore, UnknownAndMisshapenIdsAreNotFoundNamingTheId) {
  SurfaceStore store(Limits(), 1, nullptr);
  for (const char* id : {"00000000000000000000000000000000", "nope", ""}) {
    auto found = store.Find(id);
    ASSERT_FALSE(found.ok()) << id;
    EXPECT_EQ(found.status().code(), ErrorCode::kNotFound);
    EXPECT_EQ(found.status().field(), "id");
  }
}

TEST(SurfaceStore, ConcurrentRequestsForOneSurfaceFlattenItOnce) {
  SurfaceStore store(Limits(), 1, nullptr);
  const RequestClock clock(60000);
  std::atomic<int> hits{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 6; ++t) {
    threads.emplace_back([&] {
      bool hit = false;
      auto r = store.Flattened(Cylinder(2, 48), clock, &hit);
      EXPECT_TRUE(r.ok());
      if (hit) ++hits;
    });
  }
  for (auto& t : threads) t.join();
  const CacheStats stats = store.surface_stats();
  EXPECT_EQ(stats.misses, 1u);
  EXPECT_EQ(hits.load(), 5);
}

TEST(SurfaceStore, OnlyTheFlatteningTakesASlotFromAdmission) {
  SurfaceStore store(Limits(), 0, nullptr);
  Admission admission({/*slots=*/1, /*queue=*/0, /*queue_timeout_ms=*/10, /*cores=*/2});
  const RequestClock clock(60000);
  bool hit = false;
  ASSERT_TRUE(store.Flattened(Cylinder(2), clock, &hit, &admission).ok());
  EXPECT_EQ(admission.stats().admitted, 1u);

  auto held = admission.Enter();  // every slot busy, no queue
  ASSERT_TRUE(held.ok());
  // A hit needs no slot...
  auto cached = store.Flattened(Cylinder(2), clock, &hit, &admission);
  ASSERT_TRUE(cached.ok()) << cached.status().ToString();
  EXPECT_TRUE(hit);
  // ... a new flattening does, and is refused.
  auto refused = store.Flattened(Cylinder(3), clock, &hit, &admission);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), ErrorCode::kUnavailable);
  // Without admission (the caller holds its own slot) it runs.
  EXPECT_TRUE(store.Flattened(Cylinder(3), clock, &hit).ok());
}

TEST(SurfaceStore, StaysWithinItsBytesAndForgetsTheLeastRecent) {
  ServiceLimits limits = Limits();
  SurfaceStore probe(limits, 1, nullptr);
  const RequestClock clock(60000);
  bool hit = false;
  const size_t one = (*probe.Flattened(Cylinder(2), clock, &hit))->bytes;
  limits.cache_bytes = one + one / 2;  // room for one
  SurfaceStore store(limits, 1, nullptr);
  auto a = store.Flattened(Cylinder(2), clock, &hit);
  auto b = store.Flattened(Cylinder(3), clock, &hit);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_FALSE(store.Find((*a)->id).ok());
  EXPECT_TRUE(store.Find((*b)->id).ok());
  EXPECT_EQ(store.surface_stats().evictions, 1u);
  EXPECT_LE(store.surface_stats().bytes, limits.cache_bytes);
}

TEST(SurfaceStore, GridsPastTheLimitAreRefusedBeforeAnyWork) {
  ServiceLimits limits = Limits();
  limits.max_grid_side = 16;
  SurfaceStore store(limits, 1, nullptr);
  bool hit = false;
  auto r = store.Flattened(Cylinder(2, 17), RequestClock(60000), &hit);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(r.status().field(), "sampling.nu");
  EXPECT_EQ(store.surface_stats().misses, 0u);  // nothing computed, nothing counted
}

TEST(SurfaceStore, AnAnimationIsFlattenedOnceFrameByFrame) {
  ServiceLimits limits = Limits();
  SurfaceStore store(limits, 1, nullptr);
  const RequestClock clock(60000);
  bool hit = true;
  auto first = store.FlattenedAnimation(Swim(5), clock, 1, &hit);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  EXPECT_FALSE(hit);
  ASSERT_EQ((*first)->sheets.sheets.size(), 5u);
  EXPECT_FALSE((*first)->sheets.frames[0].warm);
  EXPECT_TRUE((*first)->sheets.frames[1].warm);
  auto again = store.FlattenedAnimation(Swim(5), clock, 1, &hit);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(hit);
  EXPECT_EQ(store.animation_stats().misses, 1u);
  EXPECT_EQ(store.surface_stats().misses, 0u);  // the surfaces' level is apart

  limits.max_animation_frames = 4;
  SurfaceStore small(limits, 1, nullptr);
  auto refused = small.FlattenedAnimation(Swim(5), clock, 1, &hit);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().field(), "animation.frames");
}

TEST(SurfaceStore, TheSecondLevelServesAnotherStoreAndIgnoresWhatFailsItsChecks) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0) << "redis-server did not start (scripts/setup.sh installs it)";
  SurfaceStore a(Limits(), 1, testing::SharedTierAt(redis.url()));
  SurfaceStore b(Limits(), 1, testing::SharedTierAt(redis.url()));
  const RequestClock clock(60000);
  bool hit = false;
  auto flat = a.Flattened(Cylinder(2), clock, &hit);
  ASSERT_TRUE(flat.ok());
  EXPECT_EQ(a.shared_tier_stats().writes, 1u);

  // By id on B: rebuilt from the second level, the same sheet.
  auto found = b.Find((*flat)->id);
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  EXPECT_EQ((*found)->sheet.flat, (*flat)->sheet.flat);
  EXPECT_EQ((*found)->request.sampling.nu, 8);
  EXPECT_EQ(b.shared_tier_stats().hits, 1u);
  // By content on B: a hit, no flattening.
  SurfaceStore c(Limits(), 1, testing::SharedTierAt(redis.url()));
  ASSERT_TRUE(c.Flattened(Cylinder(2), clock, &hit).ok());
  EXPECT_TRUE(hit);

  // A value that fails the codec's checks is refused, counted, and the
  // surface flattened here instead.
  const std::string other = proto::SurfaceId(Cylinder(3));
  redis.Command({"SET", SheetKey(other), "not a sheet"});
  SurfaceStore d(Limits(), 1, testing::SharedTierAt(redis.url()));
  EXPECT_FALSE(d.Find(other).ok());
  EXPECT_EQ(d.shared_tier_stats().corrupt, 1u);
  auto rebuilt = d.Flattened(Cylinder(3), clock, &hit);
  ASSERT_TRUE(rebuilt.ok());
  EXPECT_FALSE(hit);
  EXPECT_EQ(d.surface_stats().misses, 2u);  // the failed read, then the flattening
}

// Half a cylinder as an OBJ of 7 x 5 vertices: a surface given as a mesh.
std::string HalfCylinderObj() {
  std::string obj;
  for (int j = 0; j < 5; ++j) {
    for (int i = 0; i < 7; ++i) {
      const double a = 3.141592653589793 * i / 6;
      obj += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " " +
             std::to_string(0.5 * j) + "\n";
    }
  }
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 6; ++i) {
      const int a = 1 + i + 7 * j, b = a + 1, c = a + 8, d = a + 7;
      obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
      obj += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  }
  return obj;
}

// A surface given as a mesh is shared too: another store, whose models
// reach the same second level, rebuilds it from the value and the model,
// with the same flat vertices and no flattening.
TEST(SurfaceStore, AMeshSurfaceIsSharedWithItsFlatVertices) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0) << "redis-server did not start (scripts/setup.sh installs it)";
  ModelStore models_a(Limits(), testing::SharedTierAt(redis.url()));
  ModelStore models_b(Limits(), testing::SharedTierAt(redis.url()));
  SurfaceStore a(Limits(), 1, testing::SharedTierAt(redis.url()));
  SurfaceStore b(Limits(), 1, testing::SharedTierAt(redis.url()));
  a.UseModels(&models_a);
  b.UseModels(&models_b);
  const std::string obj = HalfCylinderObj();
  const std::string model = proto::ModelId(obj);
  bool known = true;
  ASSERT_TRUE(models_a.Put(model, obj, &known).ok());
  auto request = proto::ParseSurfaceRequest(json{
      {"surface", {{"kind", "mesh"}, {"model_id", model}}}, {"sampling", {{"nu", 9}, {"nv", 9}}}});
  ASSERT_TRUE(request.ok()) << request.status().ToString();
  const RequestClock clock(60000);
  bool hit = true;
  auto flat = a.Flattened(*request, clock, &hit);
  ASSERT_TRUE(flat.ok()) << flat.status().ToString();
  EXPECT_FALSE(hit);
  const FlatMesh* made = (*flat)->surface->flat_mesh();
  ASSERT_NE(made, nullptr);
  EXPECT_EQ(made->flat.size(), 35u);
  EXPECT_EQ(a.shared_tier_stats().writes, 1u);

  auto found = b.Find((*flat)->id);
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  const FlatMesh* rebuilt = (*found)->surface->flat_mesh();
  ASSERT_NE(rebuilt, nullptr);
  EXPECT_EQ(rebuilt->flat, made->flat);
  EXPECT_EQ(rebuilt->pairs, made->pairs);
  EXPECT_EQ((*found)->sheet.flat, (*flat)->sheet.flat);
  EXPECT_EQ((*found)->sheet.quality.stress, (*flat)->sheet.quality.stress);
  EXPECT_EQ(b.shared_tier_stats().hits, 1u);
  // The same surface point through either store's map.
  int hint = -1;
  const Vec3 at(0.3, 0.4, 0.05);
  EXPECT_EQ((*found)->map->Position(at, OutsideMode::kClamp, &hint),
            (*flat)->map->Position(at, OutsideMode::kClamp, &hint));
}

// Keys of one uploaded mesh cost a request some 70 bytes each and bring
// the mesh's vertices each: counted against the memory budget before the
// work that grows with them.
TEST(SurfaceStore, AMeshAnimationsKeysAreCountedBeforeTheyAreCopied) {
  ServiceLimits limits = Limits();
  limits.request_memory_bytes = 500 << 10;  // 35 vertices: 143 KB + 840 B a key
  ModelStore models(limits, nullptr);
  SurfaceStore store(limits, 1, nullptr);
  store.UseModels(&models);
  const std::string obj = HalfCylinderObj();
  const std::string model = proto::ModelId(obj);
  bool known = true;
  ASSERT_TRUE(models.Put(model, obj, &known).ok());
  auto animation = [&](int keys) {
    json keyframes = json::array();
    for (int k = 0; k < keys; ++k) {
      keyframes.push_back({{"time", k}, {"surface", {{"kind", "mesh"}, {"model_id", model}}}});
    }
    auto r = proto::ParseAnimateParams(
        json{{"animation", {{"keyframes", keyframes}, {"frames", 2}, {"interpolation", "linear"}}},
             {"sampling", {{"nu", 9}, {"nv", 9}}}});
    EXPECT_TRUE(r.ok()) << r.status().ToString();
    return r->animation;
  };
  const RequestClock clock(60000);
  bool hit = true;
  auto few = store.FlattenedAnimation(animation(3), clock, 1, &hit);
  EXPECT_TRUE(few.ok()) << few.status().ToString();
  auto many = store.FlattenedAnimation(animation(1000), clock, 1, &hit);
  ASSERT_FALSE(many.ok());
  EXPECT_EQ(many.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(many.status().field(), "animation.keyframes");
  EXPECT_NE(many.status().message().find("between 1000 keyframes"), std::string::npos)
      << many.status().message();
}

// An edit started from the previous sheet (a live edit's warm start): the
// same surface within 1e-6 of a cold flattening's stress, in fewer
// iterations; a sheet of another grid is not used.
TEST(SurfaceStore, AWarmStartFromTheSheetBeforeAnEditMatchesAColdStartInFewerIterations) {
  const BezierSpec figure10 = testing::LoadBezierFile(testing::DataPath("figure10.json"));
  auto request = [&](double lift, int n) {
    proto::SurfaceRequest r;
    BezierSpec b = figure10;
    b.control_points[5].z() += lift;  // 1% of the 10-unit patch per 0.1
    r.surface = b;
    r.sampling = {n, n};
    return r;
  };
  const RequestClock clock(60000);
  bool hit = false;
  for (int n : {16, 32}) {
    SurfaceStore warm_store(Limits(), 1, nullptr), cold_store(Limits(), 1, nullptr);
    auto before = warm_store.Flattened(request(0.0, n), clock, &hit);
    ASSERT_TRUE(before.ok());
    auto warm = warm_store.Flattened(request(0.1, n), clock, &hit, nullptr, {false, before->get()});
    auto cold = cold_store.Flattened(request(0.1, n), clock, &hit);
    ASSERT_TRUE(warm.ok() && cold.ok());
    const FlattenQuality& w = (*warm)->sheet.quality;
    const FlattenQuality& c = (*cold)->sheet.quality;
    EXPECT_NEAR(w.stress, c.stress, 1e-6 * c.stress) << n;
    EXPECT_LT(w.iterations, c.iterations) << n;
    EXPECT_EQ((*warm)->id, (*cold)->id);  // the id names the surface, not the path to it
  }
  // A sheet of another grid is no start: the result is the cold one.
  SurfaceStore a(Limits(), 1, nullptr), b(Limits(), 1, nullptr);
  auto other_grid = a.Flattened(request(0.0, 16), clock, &hit);
  auto ignored = a.Flattened(request(0.1, 24), clock, &hit, nullptr, {true, other_grid->get()});
  auto cold = b.Flattened(request(0.1, 24), clock, &hit);
  ASSERT_TRUE(ignored.ok() && cold.ok());
  EXPECT_EQ((*ignored)->sheet.flat, (*cold)->sheet.flat);
  EXPECT_EQ((*ignored)->sheet.quality.refollowed_paths, 0);
}

// A chain of edits, each from the one before with the paths kept (as POST
// /v1/surfaces does): the distances are measured from the previous edit's
// paths, and the stress stays within 1e-6 of a cold flattening's on every
// one of 30 edits, as live editing needs (the paths do not drift, and no pair
// is left on its path once its chord turns little enough to be measured
// directly, as a cold measurement does: carrying the turn of an earlier
// edit instead reached 1.8e-6 by the 30th edit). Without kept paths, the edit measures
// afresh and says so.
TEST(SurfaceStore, EditsMeasureFromThePreviousEditsPathsWithoutDrift) {
  const BezierSpec figure10 = testing::LoadBezierFile(testing::DataPath("figure10.json"));
  auto request = [&](int edit) {
    proto::SurfaceRequest r;
    BezierSpec b = figure10;
    b.control_points[5].z() += 0.1 * edit;  // 1% of the patch per edit
    r.surface = b;
    r.sampling = {16, 16};
    return r;
  };
  const RequestClock clock(60000);
  bool hit = false;
  SurfaceStore store(Limits(), 1, nullptr);
  auto previous = store.Flattened(request(0), clock, &hit, nullptr, {true, nullptr});
  ASSERT_TRUE(previous.ok());
  EXPECT_EQ((*previous)->sheet.quality.refollowed_paths, 0);
  EXPECT_EQ(store.edit_paths_stats().entries, 1u);
  constexpr int kEdits = 30;
  for (int e = 1; e <= kEdits; ++e) {
    auto warm = store.Flattened(request(e), clock, &hit, nullptr, {true, previous->get()});
    SurfaceStore cold_store(Limits(), 1, nullptr);
    auto cold = cold_store.Flattened(request(e), clock, &hit);
    ASSERT_TRUE(warm.ok() && cold.ok());
    const FlattenQuality& w = (*warm)->sheet.quality;
    const FlattenQuality& c = (*cold)->sheet.quality;
    // Figure 10 at 16 x 16 bends enough that nearly every pair follows a path.
    EXPECT_GT(w.refollowed_paths, 3000) << e;
    EXPECT_NEAR(w.stress, c.stress, 1e-6 * c.stress) << e;
    // Each edit after the first starts ahead along the one before (the
    // same raise: a step of 1); the first started from a cold sheet.
    if (e == 1) {
      EXPECT_EQ(w.extrapolated, 0.0);
    } else {
      EXPECT_NEAR(w.extrapolated, 1.0, 1e-9) << e;
      EXPECT_LT(w.iterations, c.iterations / 2) << e;
    }
    previous = warm;
  }
  EXPECT_EQ(store.edit_paths_stats().entries, kEdits + 1u);
  EXPECT_EQ(store.edit_paths_stats().hits, static_cast<size_t>(kEdits));  // each found the last's
  EXPECT_EQ(store.edit_paths_stats().misses, 0u);
  // The first surface flattened without keeping its paths: the edit after it
  // measures afresh.
  SurfaceStore plain(Limits(), 1, nullptr);
  auto first = plain.Flattened(request(0), clock, &hit);
  auto edit = plain.Flattened(request(1), clock, &hit, nullptr, {true, first->get()});
  ASSERT_TRUE(edit.ok());
  EXPECT_EQ((*edit)->sheet.quality.refollowed_paths, 0);
  EXPECT_EQ(plain.edit_paths_stats().entries, 1u);
  EXPECT_EQ(plain.edit_paths_stats().misses, 1u);
}

}  // namespace
}  // namespace surfdeform
