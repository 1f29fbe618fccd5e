#include "algorithms/common/fixed_order.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "algorithms/kernels/lanes.h"

namespace fogpipe::fixed_order {
namespace {

// The runtime-order buffer holds the lanes of kernels compiled for AVX2 beside the baseline
// (FOGPIPE_LANE_KERNEL, kernels/lanes.h), which read it with 32-byte aligned loads, while the
// baseline's std::allocator aligns a Lanes4 to 16 bytes only: every block must be aligned to 32
// whatever malloc returns (half of its 16-byte aligned blocks would not be), and start at zero.
TEST(FixedOrderBuffer, RuntimeOrderBlocksAreAlignedForVectorLanesAndStartAtZero) {
  std::vector<std::unique_ptr<Buffer<0, kernels::Lanes4>>> buffers;
  for (int p = 1; p <= 64; ++p) {
    buffers.push_back(std::make_unique<Buffer<0, kernels::Lanes4>>(p));
    const kernels::Lanes4* data = buffers.back()->get();
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(data) % 32, 0u) << "p = " << p;
    for (int i = 0; i < p; ++i)
      for (int m = 0; m < 4; ++m) EXPECT_EQ(data[i][m], 0.0) << "p = " << p;
  }
}

TEST(FixedOrderBuffer, CompileTimeOrdersKeepTheirValuesInPlace) {
  Buffer<3> buffer(3);
  double* data = buffer.get();
  for (int i = 0; i < 3; ++i) data[i] = i + 0.5;
  EXPECT_EQ(buffer.data + 0, data);
  EXPECT_EQ(data[2], 2.5);
}

}  // namespace
}  // namespace fogpipe::fixed_order
