// The second level on disk (service/disk_tier.hpp): values outlive the
// tier that wrote them, are checked when read back (a damaged file is
// removed and counted, never returned), fit the byte budget (least
// recently used out first), and one directory serves one process.
#include "service/disk_tier.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace surfdeform {
namespace {

namespace fs = std::filesystem;

class DiskTierTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("surfdeform-disk-tier-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::unique_ptr<SharedTier> Open(size_t budget = 1 << 20) {
    auto tier = CreateDiskTier({dir_.string(), budget});
    EXPECT_TRUE(tier.ok()) << tier.status().ToString();
    return tier.ok() ? std::move(*tier) : nullptr;
  }
  std::vector<fs::path> Files() const {
    std::vector<fs::path> out;
    for (const auto& e : fs::recursive_directory_iterator(dir_ / "objects")) {
      if (e.is_regular_file()) out.push_back(e.path());
    }
    return out;
  }
  fs::path dir_;
};

TEST_F(DiskTierTest, ValuesOutliveTheProcessThatWroteThem) {
  {
    auto tier = Open();
    tier->Put("model:a", "the bytes of a");
    std::string v;
    EXPECT_EQ(tier->Get("model:a", &v), SharedTier::Lookup::kHit);
    EXPECT_EQ(v, "the bytes of a");
    EXPECT_EQ(tier->Get("model:b", &v), SharedTier::Lookup::kMiss);
    EXPECT_TRUE(tier->retention().survives_restart);
    EXPECT_STREQ(tier->stats().kind, "disk");
  }
  auto again = Open();
  std::string v;
  EXPECT_TRUE(again->Exists("model:a"));
  EXPECT_EQ(again->Get("model:a", &v), SharedTier::Lookup::kHit);
  EXPECT_EQ(v, "the bytes of a");
}

TEST_F(DiskTierTest, ADamagedFileIsRemovedAndCountedNeverReturned) {
  auto tier = Open();
  tier->Put("sheet:x", std::string(1000, 'x'));
  ASSERT_EQ(Files().size(), 1u);
  {
    std::fstream f(Files()[0], std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-10, std::ios::end);
    f.put('y');  // one byte of the value changed: its digest no longer matches
  }
  std::string v;
  EXPECT_EQ(tier->Get("sheet:x", &v), SharedTier::Lookup::kMiss);
  EXPECT_TRUE(v.empty());
  EXPECT_EQ(tier->stats().corrupt, 1u);
  EXPECT_TRUE(Files().empty());
  EXPECT_FALSE(tier->Exists("sheet:x"));
}

TEST_F(DiskTierTest, TheBudgetKeepsTheMostRecentlyUsed) {
  auto tier = Open(/*budget=*/3 * 1200);
  tier->Put("a", std::string(1000, 'a'));
  tier->Put("b", std::string(1000, 'b'));
  tier->Put("c", std::string(1000, 'c'));
  std::string v;
  ASSERT_EQ(tier->Get("a", &v), SharedTier::Lookup::kHit);  // a used: b is the oldest now
  tier->Put("d", std::string(1000, 'd'));
  EXPECT_TRUE(tier->Exists("a"));
  EXPECT_FALSE(tier->Exists("b"));
  EXPECT_TRUE(tier->Exists("c"));
  EXPECT_TRUE(tier->Exists("d"));
  EXPECT_EQ(Files().size(), 3u);
}

TEST_F(DiskTierTest, OneDirectoryServesOneProcess) {
  auto first = Open();
  auto second = CreateDiskTier({dir_.string(), 1 << 20});
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.status().message().find("in use"), std::string::npos);
  first.reset();
  EXPECT_TRUE(CreateDiskTier({dir_.string(), 1 << 20}).ok());  // free again
}

TEST_F(DiskTierTest, WritesCutShortByACrashAreDropped) {
  { Open(); }
  fs::create_directories(dir_ / "tmp");
  std::ofstream(dir_ / "tmp" / "half-written") << "partial";
  auto tier = Open();
  EXPECT_FALSE(fs::exists(dir_ / "tmp" / "half-written"));
  EXPECT_TRUE(Files().empty());
}

}  // namespace
}  // namespace surfdeform
