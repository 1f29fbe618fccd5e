// Tests pipeline/graph/memory_budget.cpp: what the budget leaves for recordings.
// (ParseByteSize, BytesPerAxis and AxesInFlight are also exercised in inputs_test.cpp.)
#include "pipeline/graph/memory_budget.h"

#include <gtest/gtest.h>

namespace fogpipe::graph {
namespace {

constexpr std::uint64_t kMiB = 1ull << 20;

TEST(MemoryBudget, FixedBytesAreThe32MiBProcessBaseAnd2MiBPerWriterThread) {
  EXPECT_EQ(FixedBytes(1), 34 * kMiB);
  EXPECT_EQ(FixedBytes(2), 36 * kMiB);
  EXPECT_EQ(FixedBytes(0), FixedBytes(1));  // 0 threads is treated as 1
}

TEST(MemoryBudget, RecordingsGetTheBudgetMinusTheFixedBytesAndNothingBelowThem) {
  EXPECT_EQ(BytesForRecordings(256 * kMiB, 2), 220 * kMiB);
  EXPECT_EQ(BytesForRecordings(36 * kMiB, 2), 0u);
  EXPECT_EQ(BytesForRecordings(10 * kMiB, 2), 0u);
}

TEST(MemoryBudget, AHundredHertzHourFitsOnceIn384MiBWithTwoThreads) {
  // 360000 samples: 19 expected IMFs -> (2 x 20 + 8 + 52) x N x 8 bytes = 288 MB per axis.
  const std::uint64_t per_axis = BytesPerAxis(360000, 0);
  EXPECT_EQ(per_axis, 100ull * 360000 * 8);
  EXPECT_EQ(AxesInFlight(BytesForRecordings(384 * kMiB, 2), per_axis), 1);
  EXPECT_EQ(AxesInFlight(BytesForRecordings(2048 * kMiB, 2), per_axis), 7);
}

}  // namespace
}  // namespace fogpipe::graph
