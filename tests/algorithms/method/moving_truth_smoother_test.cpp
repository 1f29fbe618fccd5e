// Method 1 with the RTS smoother against method 1 with its filter on the moving-truth grid
// (moving_truth.h), test seeds 101-105 (the design seeds of docs/filtering.md, "S5", were 1-5 and
// 6-8): smoothing must not lose to filtering.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "algorithms/method/method.h"
#include "tests/algorithms/method/moving_truth.h"

namespace fogpipe::method {
namespace {

// A smoother on a correctly specified model cannot lose to its filter in expectation; on EMD
// components whose AR models take band-passed noise for signal it did (by more than 1e-4 of the
// RMS error on 12 of the 45 design records and 10 of the 27 check records, up to 3.4 %), and the
// model check of the smoother (rts_smoother.h, SmootherContradictsModel) hands those components
// the filter's output. Bound: a loss above 1e-4 of the RMS error counts, as in docs/filtering.md;
// what the kept smoothers still move is far below it (measured at most 3.4e-8 relative on the
// design records). Had the loss rate per record stayed at the design seeds' 12 / 45, 0 losses in
// 45 records would have probability (33 / 45)^45 ~ 1e-6, so the assertion separates the two.
// Per component the kept output must also honour the model's prediction that the smoothed
// residuals' mean square is at least the filtered ones'.
TEST(MovingTruthSmoother, NeverLosesToItsFilterOnAnyRecord) {
  int losses = 0, records = 0, replaced = 0;
  double worst = 0.0;
  for (const testing::MovingTruthRecord& r : testing::MovingTruthGrid({101, 102, 103, 104, 105})) {
    MethodOptions options;
    options.component.kalman.smooth = true;
    options.reference.enabled = false;
    const MethodResult m = RunMethod(r.rate_rad_s, r.sample_rate_hz, options);
    ASSERT_TRUE(HasResult(m.summary.termination)) << m.summary.message;
    Eigen::VectorXd filtered = Eigen::VectorXd::Zero(m.method1.size());
    const int num_imfs = m.summary.num_imfs;
    for (int k = 0; k <= num_imfs; ++k) {
      const ComponentModel& c = m.components[k];
      filtered += c.kalman.filtered;
      const Eigen::VectorXd& z = k < num_imfs ? m.decomposition.imfs[k] : m.decomposition.residue;
      EXPECT_GE((z - c.Output()).squaredNorm(), (z - c.kalman.filtered).squaredNorm())
          << r.scenario << " N " << r.n_deg_sqrt_h << " seed " << r.seed << " component " << k;
      replaced += c.kalman.summary.smoother_replaced;
    }
    const double smooth_rms =
        testing::RmsAgainstTruth(m.method1, m.preprocessed, r.true_rate_rad_s);
    const double filter_rms = testing::RmsAgainstTruth(filtered, m.preprocessed, r.true_rate_rad_s);
    const double ratio = smooth_rms / filter_rms;
    worst = std::max(worst, ratio);
    losses += ratio > 1.0 + 1e-4;
    ++records;
  }
  RecordProperty("worst_smoother_over_filter", std::to_string(worst));
  RecordProperty("components_replaced", std::to_string(replaced));
  std::printf("smoother / filter RMS: worst %.9f over %d records, %d components replaced\n", worst,
              records, replaced);
  EXPECT_EQ(records, 45);
  EXPECT_EQ(losses, 0) << "worst ratio " << worst;
}

}  // namespace
}  // namespace fogpipe::method
