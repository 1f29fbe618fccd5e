// The moving-truth table of docs/filtering.md (a study, DISABLED_: about a minute of CPU per
// seed): on the grid of moving_truth.h (seeds 1-5), the RMS error against the truth of raw,
// method 1 (filter and --smooth), method 2 and each reference filter, as medians per scenario and
// noise level of the ratio to raw. Run with --gtest_also_run_disabled_tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>

#include "algorithms/method/method.h"
#include "tests/algorithms/method/moving_truth.h"

namespace fogpipe::method {
namespace {

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

TEST(MovingTruthTable, DISABLED_PrintsTheRmsRatiosToRawOfEveryMethod) {
  const std::vector<std::string> columns = {"method1",        "method1_smooth", "method2",
                                            "butterworth",    "moving_average", "rw_kalman",
                                            "rw_rts",         "best_ref"};
  std::map<std::string, std::map<std::string, std::vector<double>>> ratios;  // cell -> column
  std::vector<std::string> cells;
  int m1_beats_m2 = 0, records = 0;
  double worst_ref_over_raw = 0.0;
  for (const testing::MovingTruthRecord& r : testing::MovingTruthGrid({1, 2, 3, 4, 5})) {
    MethodOptions options;
    const MethodResult filter = RunMethod(r.rate_rad_s, r.sample_rate_hz, options);
    options.component.kalman.smooth = true;
    options.reference.enabled = false;
    const MethodResult smooth = RunMethod(r.rate_rad_s, r.sample_rate_hz, options);
    ASSERT_TRUE(HasResult(filter.summary.termination)) << filter.summary.message;
    ASSERT_TRUE(HasResult(smooth.summary.termination)) << smooth.summary.message;
    auto rms = [&](const MethodResult& m, const Eigen::VectorXd& e) {
      return testing::RmsAgainstTruth(e, m.preprocessed, r.true_rate_rad_s);
    };
    const double raw = rms(filter, filter.preprocessed.signal);
    char cell[64];
    std::snprintf(cell, sizeof(cell), "%s N=%.2f", r.scenario.c_str(), r.n_deg_sqrt_h);
    if (ratios.find(cell) == ratios.end()) cells.push_back(cell);
    auto& row = ratios[cell];
    const double m1 = rms(filter, filter.method1), m2 = rms(filter, filter.direct.Output());
    row["method1"].push_back(m1 / raw);
    row["method1_smooth"].push_back(rms(smooth, smooth.method1) / raw);
    row["method2"].push_back(m2 / raw);
    double best = 1e300;
    for (const ReferenceEvaluation& e : filter.reference) {
      const double v = rms(filter, e.output.signal);
      row[e.output.name].push_back(v / raw);
      best = std::min(best, v);
      worst_ref_over_raw = std::max(worst_ref_over_raw, v / raw);
    }
    row["best_ref"].push_back(best / raw);
    row["method1_over_best_ref"].push_back(m1 / best);
    m1_beats_m2 += m1 < m2;
    ++records;
  }
  std::printf("| scenario | ");
  for (const auto& c : columns) std::printf("%s | ", c.c_str());
  std::printf("method1 / best_ref |\n|---|");
  for (std::size_t i = 0; i <= columns.size(); ++i) std::printf("---|");
  std::printf("\n");
  for (const std::string& cell : cells) {
    std::printf("| %s | ", cell.c_str());
    for (const auto& c : columns) std::printf("%.3f | ", Median(ratios[cell][c]));
    std::printf("%.2f |\n", Median(ratios[cell]["method1_over_best_ref"]));
  }
  std::printf("method 1 beats method 2 on %d of %d records; worst reference / raw %.3f\n",
              m1_beats_m2, records, worst_ref_over_raw);
}

}  // namespace
}  // namespace fogpipe::method
