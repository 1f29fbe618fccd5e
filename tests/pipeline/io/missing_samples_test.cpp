#include "pipeline/io/missing_samples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace fogpipe::io {
namespace {

const double kNan = std::numeric_limits<double>::quiet_NaN();

TEST(BridgeNanRuns, ReplacesAnInteriorRunByTheStraightLineBetweenItsNeighbours) {
  Eigen::VectorXd x(6);
  x << 1.0, kNan, kNan, kNan, 5.0, 6.0;
  BridgeReport report;
  ASSERT_TRUE(BridgeNanRuns(x, 3, &report));
  EXPECT_DOUBLE_EQ(x[1], 2.0);
  EXPECT_DOUBLE_EQ(x[2], 3.0);
  EXPECT_DOUBLE_EQ(x[3], 4.0);
  EXPECT_EQ(report.bridged_samples, 3);
  EXPECT_EQ(report.runs, 1);
  EXPECT_EQ(report.longest_run, 3);
  EXPECT_EQ(report.longest_run_start, 1);
}

TEST(BridgeNanRuns, FillsRunsAtTheEdgesWithTheNearestValidSample) {
  Eigen::VectorXd x(5);
  x << kNan, kNan, 2.0, 3.0, kNan;
  ASSERT_TRUE(BridgeNanRuns(x, 2, nullptr));
  EXPECT_EQ(x[0], 2.0);
  EXPECT_EQ(x[1], 2.0);
  EXPECT_EQ(x[4], 3.0);
}

TEST(BridgeNanRuns, RefusesARunLongerThanTheLimitAndReportsWhere) {
  Eigen::VectorXd x(8);
  x << 1.0, kNan, 2.0, kNan, kNan, kNan, 3.0, 4.0;
  BridgeReport report;
  EXPECT_FALSE(BridgeNanRuns(x, 2, &report));
  EXPECT_EQ(report.longest_run, 3);
  EXPECT_EQ(report.longest_run_start, 3);
  EXPECT_EQ(report.runs, 2);
  EXPECT_DOUBLE_EQ(x[1], 1.5);  // the short run is still bridged
}

TEST(BridgeNanRuns, RefusesInfinityWhichIsNotAMissingSampleMarker) {
  Eigen::VectorXd x(4);
  x << 1.0, std::numeric_limits<double>::infinity(), 2.0, 3.0;
  BridgeReport report;
  EXPECT_FALSE(BridgeNanRuns(x, 10, &report));
  EXPECT_EQ(report.infinite_samples, 1);
  EXPECT_EQ(report.first_infinite_index, 1);
}

TEST(BridgeNanRuns, LeavesACleanSignalUntouched) {
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(100, -1.0, 1.0);
  const Eigen::VectorXd copy = x;
  BridgeReport report;
  EXPECT_TRUE(BridgeNanRuns(x, 0, &report));
  EXPECT_EQ(x, copy);
  EXPECT_EQ(report.runs, 0);
}

}  // namespace
}  // namespace fogpipe::io
