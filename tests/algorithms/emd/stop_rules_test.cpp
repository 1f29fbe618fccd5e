#include "algorithms/emd/stop_rules.h"

#include <gtest/gtest.h>

namespace fogpipe::emd {
namespace {

ExtremaCounts Counts(int maxima, int minima, int zero_crossings) {
  ExtremaCounts c;
  c.num_maxima = maxima;
  c.num_minima = minima;
  c.num_zero_crossings = zero_crossings;
  return c;
}

TEST(StopRules, FixedCountStopsAtExactlyThatManySifts) {
  StopCriteria criteria;
  criteria.fixed_sifts = 3;
  SiftStopper stopper(criteria, Counts(10, 10, 20));
  SiftStop reason;
  EXPECT_FALSE(stopper.ShouldStop(1, Counts(10, 10, 20), {}, 100, &reason));
  EXPECT_FALSE(stopper.StopsAt(2));
  EXPECT_FALSE(stopper.ShouldStop(2, Counts(10, 10, 20), {}, 100, &reason));
  EXPECT_TRUE(stopper.StopsAt(3));
  ASSERT_TRUE(stopper.ShouldStop(3, Counts(10, 10, 20), {}, 100, &reason));
  EXPECT_EQ(reason, SiftStop::kFixedCount);
}

TEST(StopRules, CauchyStopsWhenTheMeanEnergyRatioFallsBelowTheThreshold) {
  StopCriteria criteria;
  criteria.stop_rule = StopRule::kCauchy;
  criteria.cauchy_sd = 0.2;
  SiftStopper stopper(criteria, Counts(10, 10, 20));
  SiftStatistics stats;
  stats.sum_input_sq = 100.0;
  stats.sum_mean_sq = 25.0;  // SD = 0.25.
  SiftStop reason;
  EXPECT_FALSE(stopper.ShouldStop(1, Counts(10, 10, 20), stats, 100, &reason));
  stats.sum_mean_sq = 19.0;  // SD = 0.19.
  ASSERT_TRUE(stopper.ShouldStop(2, Counts(10, 10, 20), stats, 100, &reason));
  EXPECT_EQ(reason, SiftStop::kThresholdMet);
}

TEST(StopRules, SNumberNeedsSConsecutiveSiftsWithUnchangedImfCounts) {
  StopCriteria criteria;
  criteria.stop_rule = StopRule::kSNumber;
  criteria.s_number = 2;
  SiftStopper stopper(criteria, Counts(12, 12, 20));
  SiftStop reason;
  EXPECT_FALSE(stopper.ShouldStop(1, Counts(10, 10, 19), {}, 100, &reason));  // Changed.
  EXPECT_FALSE(stopper.ShouldStop(2, Counts(10, 10, 19), {}, 100, &reason));  // Stable 1.
  EXPECT_FALSE(stopper.ShouldStop(3, Counts(10, 10, 20), {}, 100, &reason));  // Changed: reset.
  EXPECT_FALSE(stopper.ShouldStop(4, Counts(10, 10, 20), {}, 100, &reason));  // Stable 1.
  ASSERT_TRUE(stopper.ShouldStop(5, Counts(10, 10, 20), {}, 100, &reason));   // Stable 2.
  EXPECT_EQ(reason, SiftStop::kSNumberMet);
}

TEST(StopRules, SNumberIgnoresStableCountsThatAreNotAnImf) {
  StopCriteria criteria;
  criteria.stop_rule = StopRule::kSNumber;
  criteria.s_number = 1;
  criteria.max_sifts = 3;
  SiftStopper stopper(criteria, Counts(10, 10, 10));  // 20 extrema, 10 zero crossings.
  SiftStop reason;
  EXPECT_FALSE(stopper.ShouldStop(1, Counts(10, 10, 10), {}, 100, &reason));
  EXPECT_FALSE(stopper.ShouldStop(2, Counts(10, 10, 10), {}, 100, &reason));
  ASSERT_TRUE(stopper.ShouldStop(3, Counts(10, 10, 10), {}, 100, &reason));
  EXPECT_EQ(reason, SiftStop::kSiftCap);
}

TEST(StopRules, RillingNeedsAllThreeThresholdsAndImfCounts) {
  StopCriteria criteria;
  criteria.stop_rule = StopRule::kRilling;  // theta1 0.05, theta2 0.5, alpha 0.05.
  SiftStopper stopper(criteria, Counts(10, 10, 20));
  SiftStatistics stats;
  SiftStop reason;
  stats.num_over_theta1 = 6;  // 6 % of 100 samples > alpha.
  EXPECT_FALSE(stopper.ShouldStop(1, Counts(10, 10, 20), stats, 100, &reason));
  stats.num_over_theta1 = 5;
  stats.num_over_theta2 = 1;  // One sample above theta2.
  EXPECT_FALSE(stopper.ShouldStop(2, Counts(10, 10, 20), stats, 100, &reason));
  stats.num_over_theta2 = 0;
  EXPECT_FALSE(stopper.ShouldStop(3, Counts(10, 10, 17), stats, 100, &reason));  // Not an IMF.
  ASSERT_TRUE(stopper.ShouldStop(4, Counts(10, 10, 19), stats, 100, &reason));
  EXPECT_EQ(reason, SiftStop::kRillingMet);
}

TEST(StopRules, TheSiftCapStopsEveryRule) {
  for (StopRule rule : {StopRule::kCauchy, StopRule::kSNumber, StopRule::kRilling}) {
    StopCriteria criteria;
    criteria.stop_rule = rule;
    criteria.max_sifts = 2;
    SiftStopper stopper(criteria, Counts(10, 10, 5));
    SiftStatistics never;  // Cauchy SD = 1, Rilling: every sample over both thresholds.
    never.sum_mean_sq = never.sum_input_sq = 1.0;
    never.num_over_theta1 = never.num_over_theta2 = 100;
    SiftStop reason;
    EXPECT_FALSE(stopper.ShouldStop(1, Counts(10, 10, 5), never, 100, &reason));
    EXPECT_TRUE(stopper.StopsAt(2));
    ASSERT_TRUE(stopper.ShouldStop(2, Counts(10, 10, 5), never, 100, &reason));
    EXPECT_EQ(reason, SiftStop::kSiftCap) << ToString(rule);
  }
}

TEST(StopRules, NamesAreStable) {
  EXPECT_STREQ(ToString(StopRule::kFixedSifts), "fixed_sifts");
  EXPECT_STREQ(ToString(StopRule::kCauchy), "cauchy");
  EXPECT_STREQ(ToString(StopRule::kSNumber), "s_number");
  EXPECT_STREQ(ToString(StopRule::kRilling), "rilling");
  EXPECT_STREQ(ToString(SiftStop::kFixedCount), "fixed_count");
  EXPECT_STREQ(ToString(SiftStop::kThresholdMet), "threshold_met");
  EXPECT_STREQ(ToString(SiftStop::kSNumberMet), "s_number_met");
  EXPECT_STREQ(ToString(SiftStop::kRillingMet), "rilling_met");
  EXPECT_STREQ(ToString(SiftStop::kSiftCap), "sift_cap");
  EXPECT_STREQ(ToString(SiftStop::kTooFewExtrema), "too_few_extrema");
}

}  // namespace
}  // namespace fogpipe::emd
