// Tests pipeline/io/spill_store.cpp: columns come back bit for bit, from several threads, and the
// scratch file leaves nothing in its folder.
#include "pipeline/io/spill_store.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

namespace fogpipe::io {
namespace {

namespace fs = std::filesystem;
using Kind = method::ComponentStore::Kind;

fs::path FreshFolder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / ("fogpipe_spill_test_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

int EntriesIn(const fs::path& folder) {
  int count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++count;
  return count;
}

Eigen::VectorXd Noise(Eigen::Index n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = normal(rng);
  return x;
}

TEST(SpillStore, ColumnsComeBackBitForBitIncludingNonFiniteValues) {
  const fs::path folder = FreshFolder("round_trip");
  SpillStore store(folder.string());
  Eigen::VectorXd a = Noise(100003, 1);
  a[5] = std::numeric_limits<double>::quiet_NaN();
  a[6] = -0.0;
  a[7] = std::numeric_limits<double>::infinity();
  a[8] = std::numeric_limits<double>::denorm_min();
  const Eigen::VectorXd b = Noise(17, 2);
  store.Put(Kind::kComponent, 0, a);
  store.Put(Kind::kFiltered, 0, b);
  EXPECT_TRUE(store.Has(Kind::kComponent, 0));
  EXPECT_FALSE(store.Has(Kind::kComponent, 1));
  Eigen::VectorXd back;
  store.Get(Kind::kComponent, 0, &back);
  ASSERT_EQ(back.size(), a.size());
  EXPECT_EQ(std::memcmp(back.data(), a.data(), sizeof(double) * a.size()), 0);
  store.Get(Kind::kFiltered, 0, &back);
  EXPECT_TRUE(back == b);
  EXPECT_EQ(store.bytes(), sizeof(double) * (a.size() + b.size()));
}

TEST(SpillStore, AColumnNeverStoredIsAnErrorNamingTheFolder) {
  const fs::path folder = FreshFolder("missing");
  SpillStore store(folder.string());
  Eigen::VectorXd x;
  try {
    store.Get(Kind::kComponent, 3, &x);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(folder.string()), std::string::npos) << e.what();
  }
}

TEST(SpillStore, ManyThreadsPuttingAndGettingAtOnceKeepEveryColumnApart) {
  const fs::path folder = FreshFolder("threads");
  SpillStore store(folder.string());
  const int columns = 24;
  std::vector<std::thread> threads;
  for (int k = 0; k < columns; ++k) {
    threads.emplace_back([&store, k] {
      store.Put(Kind::kComponent, k, Noise(50000 + k, 100 + k));
      Eigen::VectorXd back;
      store.Get(Kind::kComponent, k, &back);
      EXPECT_TRUE(back == Noise(50000 + k, 100 + k)) << k;
    });
  }
  for (std::thread& t : threads) t.join();
  for (int k = 0; k < columns; ++k) {
    Eigen::VectorXd back;
    store.Get(Kind::kComponent, k, &back);
    EXPECT_TRUE(back == Noise(50000 + k, 100 + k)) << k;
  }
}

TEST(SpillStore, AReleasedColumnIsGoneAndItsNeighboursComeBackBitForBit) {
  const fs::path folder = FreshFolder("release");
  SpillStore store(folder.string());
  // Odd lengths: the released column's ends fall inside pages its neighbours share.
  const Eigen::VectorXd a = Noise(100003, 4), b = Noise(70001, 5), c = Noise(5003, 6);
  store.Put(Kind::kComponent, 0, a);
  store.Put(Kind::kComponent, 1, b);
  store.Put(Kind::kFiltered, 0, c);
  store.Release(Kind::kComponent, 1);
  store.Release(Kind::kComponent, 7);  // never stored: nothing happens
  EXPECT_FALSE(store.Has(Kind::kComponent, 1));
  Eigen::VectorXd back;
  EXPECT_THROW(store.Get(Kind::kComponent, 1, &back), ScratchError);
  store.Get(Kind::kComponent, 0, &back);
  ASSERT_EQ(back.size(), a.size());
  EXPECT_EQ(std::memcmp(back.data(), a.data(), sizeof(double) * a.size()), 0);
  store.Get(Kind::kFiltered, 0, &back);
  ASSERT_EQ(back.size(), c.size());
  EXPECT_EQ(std::memcmp(back.data(), c.data(), sizeof(double) * c.size()), 0);
}

TEST(SpillStore, ReleasingColumnsGivesTheirSpaceBack) {
  const fs::path folder = FreshFolder("release_space");
  SpillStore store(folder.string());
  constexpr Eigen::Index kSamples = 1 << 18;  // 2 MiB per column
  for (int k = 0; k < 4; ++k) store.Put(Kind::kComponent, k, Noise(kSamples, 10 + k));
  const std::uint64_t before = store.allocated_bytes();
  if (before == 0) GTEST_SKIP() << "the file system reports no blocks for the scratch file";
  store.Release(Kind::kComponent, 1);
  store.Release(Kind::kComponent, 2);
  // Two columns' bytes (4 MiB) punched out, less at most one partial block at each end.
  const std::uint64_t released = 2 * kSamples * sizeof(double);
  EXPECT_LE(store.allocated_bytes(), before - released + 2 * 65536)
      << "before " << before << " bytes, after " << store.allocated_bytes();
}

TEST(SpillStore, TheScratchFileHasNoNameInItsFolder) {
  const fs::path folder = FreshFolder("unnamed");
  {
    SpillStore store(folder.string());
    store.Put(Kind::kComponent, 0, Noise(1000, 3));
    EXPECT_EQ(EntriesIn(folder), 0);  // a kill at this point leaves nothing behind either
  }
  EXPECT_EQ(EntriesIn(folder), 0);
}

TEST(SpillStore, AFolderThatDoesNotExistIsAnErrorNamingIt) {
  const fs::path folder = FreshFolder("absent") / "no" / "such";
  EXPECT_THROW(SpillStore(folder.string()), std::runtime_error);
  try {
    SpillStore store(folder.string());
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(folder.string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fogpipe::io
