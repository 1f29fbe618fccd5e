#include "pipeline/io/repeated_samples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/recording_reader.h"

namespace fogpipe::io {
namespace {

// A quantized gyro output in counts: white noise of `sigma_counts` on a slow random walk,
// rounded to whole counts. Its repeats cluster where the walk sits inside one count, as a real
// quantized output's do.
Eigen::VectorXd QuantizedRecord(long long n, double sigma_counts, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd x(n);
  double walk = 0.0;
  for (long long i = 0; i < n; ++i) {
    walk += 0.002 * normal(rng);
    x[i] = std::round(walk + sigma_counts * normal(rng));
  }
  return x;
}

TEST(FindRepeatedRun, FindsTheLongestRunOfOneValueAndWhereItStarts) {
  Eigen::VectorXd x(10);
  x << 1, 2, 2, 3, 3, 3, 3, 4, 4, 5;
  const RepeatedRunReport r = FindRepeatedRun(x, 0.0);
  EXPECT_EQ(r.start, 3);
  EXPECT_EQ(r.samples, 4);
  EXPECT_EQ(r.value, 3.0);
  EXPECT_EQ(r.next_longest, 2);
  EXPECT_FALSE(r.at_end);
  EXPECT_FALSE(r.flagged());
}

TEST(FindRepeatedRun, CallsATailOfTheFillValueFarLongerThanAnyRunUnwritten) {
  Eigen::VectorXd x = QuantizedRecord(5000, 1.0, 1);
  x.tail(500).setConstant(-7.0);
  const RepeatedRunReport r = FindRepeatedRun(x, -7.0);
  EXPECT_TRUE(r.unwritten_tail);
  EXPECT_EQ(r.start, 4500);
  EXPECT_EQ(r.samples, 500);
  EXPECT_NE(DescribeRepeatedRun(r, 10.0, "deg/h").find("fill value"), std::string::npos);
  // The same tail of a value that is not the fill value is a frozen output, not storage.
  const RepeatedRunReport other = FindRepeatedRun(x, 0.0);
  EXPECT_FALSE(other.unwritten_tail);
  EXPECT_TRUE(other.stuck);
  EXPECT_NE(DescribeRepeatedRun(other, 10.0, "deg/h").find("frozen output"), std::string::npos);
}

TEST(FindRepeatedRun, CallsARunInsideTheRecordFrozenOnlyWhenFarLongerThanEveryOtherRun) {
  Eigen::VectorXd x = QuantizedRecord(5000, 1.0, 2);
  const long long longest_natural = FindRepeatedRun(x, 0.0).samples;
  x.segment(2000, 4 * longest_natural).setConstant(x[1999]);
  EXPECT_FALSE(FindRepeatedRun(x, 1e9).stuck) << "4x the longest other run is not enough";
  x.segment(2000, std::max<long long>(kMinStuckRun, 5 * longest_natural)).setConstant(x[1999]);
  const RepeatedRunReport r = FindRepeatedRun(x, 1e9);
  EXPECT_TRUE(r.stuck);
  EXPECT_EQ(r.start, 1999);
  EXPECT_EQ(DescribeRepeatedRun(FindRepeatedRun(QuantizedRecord(5000, 1.0, 3), 0.0), 10.0, "deg/h"),
            "");
}

// False alarms on quantized outputs with nothing wrong, test seeds 1001-1300. The spacing of
// the two longest of many geometric run lengths with repeat probability q exceeds r samples
// with probability about q^r (repeated_samples.h); a frozen-output flag needs r >= 48 and an
// unwritten tail needs the last run to be the longest and zero. At sigma = 0.4 counts q is about
// 0.57 (measured; 0.37 at 0.7, 0.18 at 1.5), q^48 = 2e-12, so 300 records expect no false flag;
// the test allows one, for the clustering of repeats that the geometric law leaves out.
TEST(FindRepeatedRun, RaisesNoFalseAlarmOnQuantizedOutputsOverManySeeds) {
  int flagged = 0, records = 0;
  long long longest = 0;
  for (double sigma : {0.4, 0.7, 1.5}) {
    for (unsigned seed = 1001; seed <= 1100; ++seed) {
      const RepeatedRunReport r = FindRepeatedRun(QuantizedRecord(100000, sigma, seed), 0.0);
      flagged += r.flagged() ? 1 : 0;
      longest = std::max(longest, r.samples);
      ++records;
    }
  }
  RecordProperty("longest_run_samples", static_cast<int>(longest));
  EXPECT_LE(flagged, 1) << flagged << " of " << records << " records flagged";
}

// Detection of an unwritten tail (seeds 2001-2200): a tail of the fill value is flagged when it
// is at least kTailRatio times the longest natural run; at sigma = 0.7 counts the longest
// natural run of 1e5 samples is about 20 samples, so every tail of 256 samples or more must be
// caught, and shorter ones are caught as often as the rule's ratio allows.
TEST(FindRepeatedRun, DetectsEveryUnwrittenTailLongerThanTwiceTheLongestNaturalRun) {
  std::mt19937_64 rng(7);
  int missed_long = 0, long_tails = 0, caught_by_rule = 0, rule_says = 0;
  for (unsigned seed = 2001; seed <= 2200; ++seed) {
    Eigen::VectorXd x = QuantizedRecord(100000, 0.7, seed);
    const long long natural = FindRepeatedRun(x, 1e9).samples;
    const long long tail = 16 + static_cast<long long>(rng() % 1000);
    x.tail(tail).setConstant(0.0);
    const RepeatedRunReport r = FindRepeatedRun(x, 0.0);
    if (tail >= 256) {
      ++long_tails;
      missed_long += r.unwritten_tail ? 0 : 1;
    }
    if (static_cast<double>(tail) > kTailRatio * static_cast<double>(natural)) {
      ++rule_says;
      caught_by_rule += r.unwritten_tail ? 1 : 0;
    }
  }
  EXPECT_GT(long_tails, 100);
  EXPECT_EQ(missed_long, 0) << "of " << long_tails << " tails of 256 samples or more";
  // A tail adjoining natural zeros is longer than drawn, never shorter: every tail the rule's
  // ratio admits is caught.
  EXPECT_EQ(caught_by_rule, rule_says);
}

// Real gyros (not in the repository; skipped when absent): a MEMS IMU quantized at about 0.05
// deg/s, and a ring laser gyro whose lock-in holds zero for up to 52 samples. Neither is flagged.
TEST(FindRepeatedRun, FlagsNoColumnOfTheRealMemsAndRingLaserRecordings) {
  int checked = 0;
  for (const char* path : {"/work/shared/data/real-imu/adis16405_imu1.h5",
                           "/work/shared/data/real-rlg/psins_lasergyro.h5"}) {
    if (!std::filesystem::exists(path)) continue;
    auto lock = hdf5::LockHdf5();
    RecordingReader reader(path);
    for (int a = 0; a < reader.info().axis_count; ++a) {
      ReadReport report;
      reader.ReadAxisNative(a, ReadOptions(), &report);
      EXPECT_FALSE(report.repeats.flagged())
          << path << " axis " << a << ": "
          << DescribeRepeatedRun(report.repeats, reader.info().sample_rate_hz, "native");
      ++checked;
    }
  }
  if (checked == 0) GTEST_SKIP() << "the real recordings are not on this machine";
}

}  // namespace
}  // namespace fogpipe::io
