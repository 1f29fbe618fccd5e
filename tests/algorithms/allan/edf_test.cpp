// Tests of algorithms/allan/edf.{h,cpp}. The Stable32 comparison (allan_test) checks the EDF
// through the bounds; here it is checked against an independent closed form.
#include "algorithms/allan/edf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "algorithms/allan/phase.h"
#include "tests/algorithms/allan/simulated_gyro.h"

namespace fogpipe::allan {
namespace {

// NIST SP 1065 Table 5 (Howe, Allan & Barnes 1981, empirical fit): OADEV of white FM,
//   edf = [3 (N - 1) / (2 m) - 2 (N - 2) / N] 4 m^2 / (4 m^2 + 5),  N = number of phase points.
// A simulation (20000 records of 1000 white-FM samples, scipy-free numpy, not committed) gave
// EDF 666.3, 565.3, 285.3, 90.4 at m = 1, 2, 5, 16 against the formula's 665.8, 569.9, 283.8,
// 91.3, so the formula is good to ~1 % there. The sampled-phase convention must agree with it
// within 2 % everywhere; Greenhall's printed case 2.1a (Stable32's convention) only where it
// switches to the continuous kernel (m (d + 1) > 100), and differs by up to 17 % below.
double Sp1065WhiteFmOadevEdf(double n_phase, double m) {
  return (3.0 * (n_phase - 1.0) / (2.0 * m) - 2.0 * (n_phase - 2.0) / n_phase) * 4.0 * m * m /
         (4.0 * m * m + 5.0);
}

TEST(GreenhallEdf, SampledPhaseConventionAgreesWithTheSp1065WhiteFmFormula) {
  for (long long n_phase : {1001LL, 19983LL, 1000001LL}) {
    for (long long m : {1LL, 2LL, 5LL, 16LL, 34LL, 100LL, 1000LL}) {
      if (n_phase / m < 20) continue;
      const double simple = Sp1065WhiteFmOadevEdf(n_phase, m);
      EXPECT_NEAR(GreenhallEdf(0, 2, m, n_phase, true, true) / simple, 1.0, 0.02)
          << "N=" << n_phase << " m=" << m;
      if (m * 3 > 100)
        EXPECT_NEAR(GreenhallEdf(0, 2, m, n_phase, true, false) / simple, 1.0, 0.02)
            << "N=" << n_phase << " m=" << m;
    }
  }
  // The documented Stable32-convention excess at m = 1.
  EXPECT_NEAR(GreenhallEdf(0, 2, 1, 1001, true) / Sp1065WhiteFmOadevEdf(1001, 1), 1.17, 0.01);
}

// At m = 1 the N - 2 second differences D_i = y_{i+1} - y_i of white FM have cov(D_i, D_i) = 2,
// cov(D_i, D_{i+1}) = -1 (units of var y), so sum D_i^2 has var = 2 sum_ij cov^2 = 12k - 4 and
// mean 2k: edf = 2 mean^2 / var = 2k^2 / (3k - 1) exactly (k = N - 2).
TEST(GreenhallEdf, SampledPhaseConventionIsExactForWhiteFmAtTheSamplingInterval) {
  for (long long n_phase : {10LL, 101LL, 1001LL}) {
    const double k = static_cast<double>(n_phase - 2);
    const double exact = 2.0 * k * k / (3.0 * k - 1.0);
    EXPECT_NEAR(GreenhallEdf(0, 2, 1, n_phase, false, true), exact, 1e-9 * exact) << n_phase;
  }
}

TEST(GreenhallEdf, RejectsNoiseTypesTheVarianceCannotMeasure) {
  EXPECT_TRUE(std::isnan(GreenhallEdf(-3, 2, 4, 1000, true)));  // alpha + 2d <= 1
  EXPECT_TRUE(std::isnan(GreenhallEdf(3, 2, 4, 1000, true)));
  EXPECT_FALSE(std::isnan(GreenhallEdf(-4, 3, 4, 1000, true)));
}

// The EDF of a variance estimate is 2 E[v]^2 / Var[v] (Greenhall & Riley, eq. 2). Over R
// simulated records its estimate has a relative standard error of about sqrt(2 / R) (the sample
// variance of R nearly chi-square values; the fourth-moment correction is 6 / edf, < 10 % here),
// i.e. 2.2 % for R = 4000; we allow 4 of them, 9 %. A slip to the unmodified kernel (F = m)
// moves MDEV's white-PM EDF at m = 8 by a factor > 2.
//
// Where the checks hold (all printed; table in docs/allan-deviations.md): MDEV for every type at
// m >= 8, and at m = 2 for white PM and white FM. At m = 2 random-walk FM simulates 14 % above
// Greenhall's value (his kernel is continuous-time noise sampled; a sampled random walk differs at
// the shortest lags, as edf.h documents for white FM), i.e. the bounds are conservative there.
// TOTDEV's SP 1065 fits (alpha <= 0) hold at T / tau <= 64 (m >= 8 of 512) and overstate the EDF
// at T / tau = 256 (white FM 384 vs ~290); its white-PM rule (SP 1065's AVAR formula, as
// Stable32) overstates it at m = 32 (240 vs ~150). Those rows are not asserted. The regimes were
// read from a design run (seeds 9000 + r); the test runs on seeds 50000 + r.
struct SimulatedEdf {
  double mdev, totdev;
};

SimulatedEdf SimulatedEdfs(const testing::GyroTruth& truth, long long n, long long m, int records) {
  std::vector<double> mvar, totvar;
  for (int r = 0; r < records; ++r) {
    const Eigen::VectorXd x = MeanRemovedPhase(testing::SimulateGyro(truth, n, 1.0, 50000 + r));
    mvar.push_back(DeviationVariances(x, Deviation::kModifiedAllan, {m})[0]);
    totvar.push_back(DeviationVariances(x, Deviation::kTotal, {m})[0]);
  }
  auto edf = [](const std::vector<double>& v) {
    double mean = 0.0, var = 0.0;
    for (double a : v) mean += a;
    mean /= v.size();
    for (double a : v) var += (a - mean) * (a - mean);
    var /= v.size() - 1;
    return 2.0 * mean * mean / var;
  };
  return {edf(mvar), edf(totvar)};
}

TEST(DeviationEdf, ModifiedAndTotalEdfsMatchTheSpreadOfSimulatedEstimates) {
  constexpr int kRecords = 4000;
  const double tolerance = 4.0 * std::sqrt(2.0 / kRecords);
  const long long n = 512;
  struct Case {
    int alpha;
    testing::GyroTruth truth;
  };
  testing::GyroTruth white_pm, white_fm, rw_fm;
  white_pm.q_rad = 1.0;
  white_fm.n_rad_sqrt_s = 1.0;
  rw_fm.k_rad_s_sqrt_s = 1.0;
  for (const Case& c : {Case{2, white_pm}, Case{0, white_fm}, Case{-2, rw_fm}}) {
    for (long long m : {2LL, 8LL, 32LL}) {
      const SimulatedEdf simulated = SimulatedEdfs(c.truth, n, m, kRecords);
      const double mdev = DeviationEdf(Deviation::kModifiedAllan, c.alpha, m, n);
      const double total = DeviationEdf(Deviation::kTotal, c.alpha, m, n);
      std::cout << "  alpha " << c.alpha << " m " << m << ": MDEV edf " << mdev << " simulated "
                << simulated.mdev << "; TOTDEV edf " << total << " simulated " << simulated.totdev
                << "\n";
      if (m >= 8 || c.alpha >= 0) {
        EXPECT_NEAR(simulated.mdev / mdev, 1.0, tolerance)
            << "MDEV alpha=" << c.alpha << " m=" << m << " simulated " << simulated.mdev;
      }
      if (m >= 8 && c.alpha <= 0) {
        EXPECT_NEAR(simulated.totdev / total, 1.0, tolerance)
            << "TOTDEV alpha=" << c.alpha << " m=" << m << " simulated " << simulated.totdev;
      }
    }
  }
}

TEST(DeviationEdf, TotalVarianceUsesSp1065sFitsPerNoiseType) {
  // T / tau = 1000 / 10 = 100.
  EXPECT_DOUBLE_EQ(TotalVarianceEdf(0, 10, 1000), 150.0);
  EXPECT_DOUBLE_EQ(TotalVarianceEdf(-1, 10, 1000), 117.0 - 0.22);
  EXPECT_DOUBLE_EQ(TotalVarianceEdf(-2, 10, 1000), 93.0 - 0.36);
  // White PM: SP 1065's AVAR formula with N = 1001 phase points.
  EXPECT_DOUBLE_EQ(TotalVarianceEdf(2, 10, 1000), 1002.0 * 981.0 / (2.0 * 991.0));
  EXPECT_TRUE(std::isnan(TotalVarianceEdf(-3, 10, 1000)));
  EXPECT_TRUE(std::isnan(TotalVarianceEdf(0, 500, 1000)));  // beyond T / 2
}

// At m = 1 the F = 1 and F = m filters are the same, so both EDFs must agree. Both evaluate the
// exact basic sum, except white PM, where the unmodified path takes Greenhall's asymptote (case
// 4.2, relative error O(1 / M^2) ~ 1e-6 at M = 999): 1e-4 there.
TEST(DeviationEdf, ModifiedEqualsUnmodifiedAtTheSamplingInterval) {
  for (int alpha : {2, 1, 0, -1, -2}) {
    const double unmodified = GreenhallEdf(alpha, 2, 1, 1001, true);
    EXPECT_NEAR(GreenhallModifiedEdf(alpha, 2, 1, 1001), unmodified,
                (alpha == 2 ? 1e-4 : 1e-9) * unmodified)
        << alpha;
  }
}

}  // namespace
}  // namespace fogpipe::allan
