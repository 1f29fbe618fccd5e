// Tests of algorithms/method/sweep_grid: the grids of AR orders and Kalman scales a sweep runs.
#include "algorithms/method/sweep_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace fogpipe::method {
namespace {

TEST(SweepGrid, ParsesRangesListsAndLogSpacedScales) {
  std::vector<int> orders;
  std::string error;
  ASSERT_TRUE(ParseIntList("2:12", &orders, &error));
  EXPECT_EQ(orders.size(), 11u);
  EXPECT_EQ(orders.front(), 2);
  EXPECT_EQ(orders.back(), 12);
  ASSERT_TRUE(ParseIntList("2:8:3", &orders, &error));
  EXPECT_EQ(orders, (std::vector<int>{2, 5, 8}));
  ASSERT_TRUE(ParseIntList("6,2,4", &orders, &error));
  EXPECT_EQ(orders, (std::vector<int>{6, 2, 4}));
  EXPECT_FALSE(ParseIntList("12:2", &orders, &error));
  EXPECT_FALSE(ParseIntList("2,x", &orders, &error));

  std::vector<double> scales;
  ASSERT_TRUE(ParseScaleList("0.1,1,10", &scales, &error));
  EXPECT_EQ(scales, (std::vector<double>{0.1, 1.0, 10.0}));
  ASSERT_TRUE(ParseScaleList("0.01:100:5", &scales, &error));
  ASSERT_EQ(scales.size(), 5u);
  // Log-spaced: 0.01, 0.1, 1, 10, 100 up to rounding of pow.
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(std::log10(scales[i]), i - 2.0, 1e-12);
  EXPECT_FALSE(ParseScaleList("0:1:3", &scales, &error));
}

TEST(SweepGrid, ListsSettingsOrderMajorAndRejectsBadValues) {
  SweepGrid grid{{2, 3}, {0.1, 1.0}, {1.0, 10.0, 100.0}};
  const auto settings = GridSettings(grid);
  // Per order: the default rule, then 2 q scales x 3 R scales.
  ASSERT_EQ(settings.size(), 14u);
  EXPECT_EQ(grid.size(), 14);
  EXPECT_TRUE(settings[0].default_rule);
  EXPECT_EQ(settings[0].ar_order, 2);
  EXPECT_FALSE(settings[1].default_rule);
  EXPECT_EQ(settings[6].ar_order, 2);
  EXPECT_TRUE(settings[7].default_rule);
  EXPECT_EQ(settings[7].ar_order, 3);
  EXPECT_EQ(settings[2].r_scale, 10.0);
  EXPECT_EQ(settings[4].q_scale, 1.0);
  std::string error;
  EXPECT_TRUE(grid.IsValid(&error));
  grid.q_scales = {0.0};
  EXPECT_FALSE(grid.IsValid(&error));
}

// One Burg recursion to order P gives the models of every lower order: the order-p model of a
// recursion run to P equals a recursion run only to p (Levinson structure, Kay & Marple 1981).
// The sweep relies on this to fit each component once.

}  // namespace
}  // namespace fogpipe::method
