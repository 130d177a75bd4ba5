// The model store alone, without the service: ids from the bytes, the first
// level (known uploads, eviction by its own budget), the second level on a
// real redis-server (another store finds an upload; values that fail the
// codec's checks are refused and counted), and the codec itself.
#include "service/model_store.hpp"

#include <gtest/gtest.h>

#include <string>

#include "proto/api.hpp"
#include "service/model_codec.hpp"
#include "support/redis_process.hpp"

namespace surfdeform {
namespace {

// A unit square in z = 0 as two triangles, shifted by `dx` (a different file
// for each dx).
std::string SquareObj(int dx = 0) {
  std::string obj;
  for (const char* v : {"0 0 0", "1 0 0", "1 1 0", "0 1 0"}) {
    obj += "v " + std::string(v) + "\n";
  }
  obj += "# " + std::to_string(dx) + "\nf 1 2 3\nf 1 3 4\n";
  return obj;
}

TEST(ModelStore, AnUploadIsImportedOnceAndFoundByTheHashOfItsBytes) {
  ModelStore store(ServiceLimits{}, nullptr);
  const std::string obj = SquareObj();
  bool known = true;
  auto first = store.Put(proto::ModelId(obj), obj, &known);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  EXPECT_FALSE(known);
  EXPECT_EQ((*first)->id, proto::ModelId(obj));
  EXPECT_EQ((*first)->id.size(), 32u);
  EXPECT_EQ((*first)->imported.mesh.positions.size(), 4u);
  EXPECT_EQ((*first)->imported.mesh.triangles.size(), 2u);
  EXPECT_EQ((*first)->imported.format, MeshFormat::kObj);
  EXPECT_GE((*first)->bytes, obj.size() + 4 * sizeof(Vec3));

  auto again = store.Put(proto::ModelId(obj), obj, &known);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(known);
  EXPECT_EQ(again->get(), first->get());
  auto found = store.Find((*first)->id);
  ASSERT_TRUE(found.ok());
  EXPECT_EQ(found->get(), first->get());

  // Other bytes, another id, though the mesh is the same.
  auto other = store.Put(proto::ModelId(SquareObj(1)), SquareObj(1), &known);
  ASSERT_TRUE(other.ok());
  EXPECT_FALSE(known);
  EXPECT_NE((*other)->id, (*first)->id);
  EXPECT_EQ(store.stats().entries, 2u);
}

TEST(ModelStore, UnknownIdsAndBadMeshesAreErrorsThatKeepNothing) {
  ModelStore store(ServiceLimits{}, nullptr);
  for (const char* id : {"00000000000000000000000000000000", "nope", ""}) {
    auto found = store.Find(id);
    ASSERT_FALSE(found.ok()) << id;
    EXPECT_EQ(found.status().code(), ErrorCode::kUnknownModel);
    EXPECT_EQ(found.status().field(), "model_id");
  }
  bool known = true;
  auto bad = store.Put(proto::ModelId("v 0 0 0\nf 1 2 3\n"), "v 0 0 0\nf 1 2 3\n", &known);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(store.stats().entries, 0u);
  ServiceLimits small;
  small.max_vertices = 3;
  ModelStore strict(small, nullptr);
  auto big = strict.Put(proto::ModelId(SquareObj()), SquareObj(), &known);
  ASSERT_FALSE(big.ok());
  EXPECT_EQ(big.status().code(), ErrorCode::kLimitExceeded);
}

TEST(ModelStore, TheFirstLevelKeepsWithinItsOwnBudget) {
  ModelStore probe(ServiceLimits{}, nullptr);
  bool known = false;
  const size_t one = (*probe.Put(proto::ModelId(SquareObj()), SquareObj(), &known))->bytes;
  ServiceLimits limits;
  limits.model_cache_bytes = one + one / 2;  // room for one
  limits.cache_bytes = 1;                    // the surfaces' budget is not the models'
  ModelStore store(limits, nullptr);
  ASSERT_TRUE(store.Put(proto::ModelId(SquareObj(0)), SquareObj(0), &known).ok());
  ASSERT_TRUE(store.Put(proto::ModelId(SquareObj(1)), SquareObj(1), &known).ok());
  EXPECT_EQ(store.stats().entries, 1u);
  EXPECT_EQ(store.stats().evictions, 1u);
  auto evicted = store.Find(proto::ModelId(SquareObj(0)));
  ASSERT_FALSE(evicted.ok());
  EXPECT_EQ(evicted.status().code(), ErrorCode::kUnknownModel);
  EXPECT_TRUE(store.Find(proto::ModelId(SquareObj(1))).ok());
}

TEST(ModelCodec, RefusesAnythingButItsOwnValueForThatId) {
  const std::string obj = SquareObj();
  const std::string id = proto::ModelId(obj);
  const std::string value = EncodeModel(obj);
  auto back = DecodeModel(value, id, 1 << 20);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(*back, obj);
  EXPECT_FALSE(DecodeModel(value, proto::ModelId("other"), 1 << 20).ok());  // not its id
  EXPECT_FALSE(DecodeModel(value.substr(0, value.size() - 1), id, 1 << 20).ok());
  EXPECT_FALSE(DecodeModel(value + "x", id, 1 << 20).ok());
  EXPECT_FALSE(DecodeModel(value, id, obj.size() - 1).ok());  // past the bound
  std::string other_version = value;
  other_version[4] = 2;
  EXPECT_FALSE(DecodeModel(other_version, id, 1 << 20).ok());
  EXPECT_FALSE(DecodeModel("", id, 1 << 20).ok());
  EXPECT_FALSE(DecodeModel(obj, id, 1 << 20).ok());  // no header
}

TEST(ModelStore, TheSecondLevelServesAnotherStoreAndIgnoresWhatFailsItsChecks) {
  testing::RedisProcess redis;
  ASSERT_NE(redis.port(), 0) << "redis-server did not start (scripts/setup.sh installs it)";
  auto tier_a = testing::SharedTierAt(redis.url());
  ModelStore a(ServiceLimits{}, tier_a);
  bool known = true;
  auto up = a.Put(proto::ModelId(SquareObj()), SquareObj(), &known);
  ASSERT_TRUE(up.ok());
  EXPECT_FALSE(known);
  EXPECT_EQ(tier_a->stats().writes, 1u);

  // By id on B: imported again from the second level.
  ModelStore b(ServiceLimits{}, testing::SharedTierAt(redis.url()));
  auto found = b.Find((*up)->id);
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  EXPECT_EQ((*found)->imported.mesh.positions, (*up)->imported.mesh.positions);
  EXPECT_EQ((*found)->imported.mesh.triangles, (*up)->imported.mesh.triangles);
  // The same upload on C: known (the second level holds it), not written again.
  auto tier_c = testing::SharedTierAt(redis.url());
  ModelStore c(ServiceLimits{}, tier_c);
  ASSERT_TRUE(c.Put(proto::ModelId(SquareObj()), SquareObj(), &known).ok());
  EXPECT_TRUE(known);
  EXPECT_EQ(tier_c->stats().writes, 0u);

  // A value that fails the codec's checks: refused, counted, unknown.
  const std::string other = proto::ModelId(SquareObj(7));
  redis.Command({"SET", ModelKey(other), EncodeModel(SquareObj(8))});
  auto tier_d = testing::SharedTierAt(redis.url());
  ModelStore d(ServiceLimits{}, tier_d);
  auto refused = d.Find(other);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), ErrorCode::kUnknownModel);
  EXPECT_EQ(tier_d->stats().corrupt, 1u);
}

}  // namespace
}  // namespace surfdeform
