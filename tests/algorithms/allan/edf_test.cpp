// Tests of algorithms/allan/edf.{h,cpp}. The Stable32 comparison (allan_test) checks the EDF
// through the bounds; here it is checked against an independent closed form.
#include "algorithms/allan/edf.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace fogpipe::allan
