// Tests pipeline/graph/memory_budget.cpp: what the budget leaves for recordings.
// (ParseByteSize, BytesPerAxis and AxesInFlight are also exercised in inputs_test.cpp.)
#include "pipeline/graph/memory_budget.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

namespace fogpipe::graph {
namespace {

constexpr std::uint64_t kMiB = 1ull << 20;

TEST(MemoryBudget, FixedBytesAreThe64MiBProcessBaseAnd2MiBPerWriterThread) {
  EXPECT_EQ(FixedBytes(1), 66 * kMiB);
  EXPECT_EQ(FixedBytes(2), 68 * kMiB);
  EXPECT_EQ(FixedBytes(0), FixedBytes(1));  // 0 threads is treated as 1
}

TEST(MemoryBudget, RecordingsGetTheBudgetMinusTheFixedBytesAndNothingBelowThem) {
  EXPECT_EQ(BytesForRecordings(256 * kMiB, 2), 188 * kMiB);
  EXPECT_EQ(BytesForRecordings(68 * kMiB, 2), 0u);
  EXPECT_EQ(BytesForRecordings(10 * kMiB, 2), 0u);
}

TEST(MemoryBudget, AHundredHertzHourFitsFiveTimesIn384MiBWithTwoThreads) {
  // 360000 samples x 20 doubles x 8 bytes = 57.6 MB per axis, whatever the number of IMFs.
  const std::uint64_t per_axis = BytesPerAxis(360000);
  EXPECT_EQ(per_axis, 20ull * 360000 * 8);
  EXPECT_EQ(AxesInFlight(BytesForRecordings(384 * kMiB, 2), per_axis), 5);
  EXPECT_EQ(AxesInFlight(BytesForRecordings(2048 * kMiB, 2), per_axis), 36);
}

TEST(MemoryBudget, ADayAtOneKilohertzFitsATwentyGibibyteBudget) {
  // 8.64e7 samples: 13.8 GB; a 24 GB node's default budget (half of it) cannot hold it, a 20G
  // budget can.
  EXPECT_EQ(BytesPerAxis(86400000), 20ull * 86400000 * 8);
  EXPECT_LT(BytesPerAxis(86400000), 20ull << 30);
}

TEST(MemoryBudget, AModelKeepsItsCompensationAndReadsItsAuxChannels) {
  // 8.64e6 samples (24 h at 100 Hz): the compensation and two channels, 3 x 8 bytes each.
  EXPECT_EQ(ModelCompensationBytes(8640000, 2), 3ull * 8 * 8640000);
  EXPECT_EQ(ModelCompensationBytes(8640000, 0), 8ull * 8640000);
  EXPECT_EQ(ModelCompensationBytes(UINT64_MAX / 8, 1), UINT64_MAX);
  EXPECT_EQ(ModelCompensationBytes(1, UINT64_MAX), UINT64_MAX);
}

TEST(MemoryBudget, ParsesBinaryMultiplesAndRejectsNonsense) {
  EXPECT_EQ(ParseByteSize("2G"), 2ull << 30);
  EXPECT_EQ(ParseByteSize("512M"), 512ull << 20);
  EXPECT_EQ(ParseByteSize("512MiB"), 512ull << 20);
  EXPECT_EQ(ParseByteSize("1.5k"), 1536u);
  EXPECT_EQ(ParseByteSize("1000"), 1000u);
  EXPECT_FALSE(ParseByteSize("12X"));
  EXPECT_FALSE(ParseByteSize("-1G"));
  EXPECT_FALSE(ParseByteSize("G"));
}

TEST(MemoryBudget, AutoIsEightyPercentOfASlurmJobsMemoryElseHalfThePhysicalMemory) {
  const char* saved = std::getenv("SLURM_MEM_PER_NODE");
  const std::string restore = saved ? saved : "";
  setenv("SLURM_MEM_PER_NODE", "1000", 1);
  EXPECT_EQ(AutoMemoryBudgetBytes(), static_cast<std::uint64_t>(0.8 * 1000 * 1048576.0));
  unsetenv("SLURM_MEM_PER_NODE");
  const std::uint64_t physical = static_cast<std::uint64_t>(sysconf(_SC_PHYS_PAGES)) *
                                 static_cast<std::uint64_t>(sysconf(_SC_PAGE_SIZE));
  EXPECT_EQ(AutoMemoryBudgetBytes(), physical / 2);
  if (saved) setenv("SLURM_MEM_PER_NODE", restore.c_str(), 1);
}

TEST(MemoryBudget, AllowsAtLeastOneAxisAndFloorOfBudgetOverEstimate) {
  EXPECT_EQ(BytesPerAxis(3600), 20u * 3600u * 8u);
  EXPECT_EQ(AxesInFlight(10 * BytesPerAxis(3600) + 1, BytesPerAxis(3600)), 10);
  EXPECT_EQ(AxesInFlight(1, BytesPerAxis(3600)), 1);
  EXPECT_EQ(BytesPerAxis(UINT64_MAX), UINT64_MAX);
}

}  // namespace
}  // namespace fogpipe::graph
