// Tests of algorithms/allan/noise_model.{h,cpp}: the closed forms against their published
// landmarks (docs/method.md, "Allan variance of the noise terms"; IEEE 952 Annex C) and against
// the engine on exact signals.
#include "algorithms/allan/noise_model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/allan/allan.h"

namespace fogpipe::allan {
namespace {

// Maximum of sigma(tau) over a fine log grid: (tau at max, sigma at max).
std::pair<double, double> Peak(Term term, const TermParams& p, double lo, double hi) {
  double best_tau = lo, best = 0.0;
  for (double tau = lo; tau < hi; tau *= 1.0001) {
    const double s = std::sqrt(TermAllanVariance(term, p, tau));
    if (s > best) best = s, best_tau = tau;
  }
  return {best_tau, best};
}

// docs/method.md: Gauss-Markov peak ~0.62 sigma near tau ~1.89 Tc (2 digits published: +-0.005,
// +-0.005 Tc), for any sigma and Tc.
TEST(TermAllanVariance, GaussMarkovPeaksAt062SigmaNear189Tc) {
  for (double tc : {0.5, 10.0, 300.0}) {
    TermParams p;
    p.amplitude = 3e-6;
    p.correlation_time_s = tc;
    const auto [tau, sigma] = Peak(Term::kGaussMarkov, p, 0.01 * tc, 100 * tc);
    EXPECT_NEAR(tau / tc, 1.89, 0.005) << tc;
    EXPECT_NEAR(sigma / p.amplitude, 0.62, 0.005) << tc;
  }
}

// Its asymptotes: RRW with K^2 = q = 2 sigma^2 / Tc for tau << Tc (relative deviation
// 1 - bracket / (u^2 / 3) = 3u/4 + O(u^2) <= 7.5e-5 for u <= 1e-4, so 1e-3 is ample), and ARW with
// N^2 = q Tc^2 for tau >> Tc (relative deviation 3 / (2u) = 1.5e-5 at u = 1e5, checked to 1e-4).
TEST(TermAllanVariance, GaussMarkovApproachesRateRandomWalkAndArwAsymptotes) {
  TermParams p;
  p.amplitude = 2.0;
  p.correlation_time_s = 5.0;
  const double q = 2.0 * 4.0 / 5.0;
  for (double tau : {5e-7, 5e-5, 5e-4}) {
    EXPECT_NEAR(TermAllanVariance(Term::kGaussMarkov, p, tau) / (q * tau / 3.0), 1.0, 1e-3) << tau;
  }
  const double tau = 5e5;
  EXPECT_NEAR(TermAllanVariance(Term::kGaussMarkov, p, tau) / (q * 25.0 / tau), 1.0, 1e-4);
  // The series branch (u < 1e-2) and the closed form agree where they meet.
  const double below = TermAllanVariance(Term::kGaussMarkov, p, 0.0499999999);
  const double above = TermAllanVariance(Term::kGaussMarkov, p, 0.0500000001);
  EXPECT_NEAR(below / above, 1.0, 1e-8);
}

// docs/method.md: sinusoid peak ~0.725 W at tau ~0.371 / f0; zeros at tau = k / f0.
TEST(TermAllanVariance, SinusoidPeaksAt0725WNear0371OverF0) {
  TermParams p;
  p.amplitude = 1.0;
  p.frequency_hz = 0.2;
  const auto [tau, sigma] = Peak(Term::kSinusoid, p, 0.1, 2.5);
  EXPECT_NEAR(tau * p.frequency_hz, 0.371, 0.0005);
  EXPECT_NEAR(sigma, 0.725, 0.0005);
  EXPECT_NEAR(TermAllanVariance(Term::kSinusoid, p, 5.0), 0.0, 1e-30);
}

// The read-off landmarks of docs/method.md's table: sigma(1 s) = N, sigma(3 s) = K,
// sigma(sqrt 3 s) = Q, sigma(sqrt 2 s) = R, floor = 0.6643 B.
TEST(TermAllanVariance, IeeeTermsPassThroughTheirReadoffPoints) {
  TermParams p;
  p.amplitude = 0.37;
  EXPECT_NEAR(std::sqrt(TermAllanVariance(Term::kAngleRandomWalk, p, 1.0)), 0.37, 1e-15);
  EXPECT_NEAR(std::sqrt(TermAllanVariance(Term::kRateRandomWalk, p, 3.0)), 0.37, 1e-15);
  EXPECT_NEAR(std::sqrt(TermAllanVariance(Term::kQuantization, p, std::sqrt(3.0))), 0.37, 1e-15);
  EXPECT_NEAR(std::sqrt(TermAllanVariance(Term::kRateRamp, p, std::sqrt(2.0))), 0.37, 1e-15);
  EXPECT_NEAR(std::sqrt(TermAllanVariance(Term::kBiasInstability, p, 123.0)) / 0.37, 0.6643, 5e-5);
}

// Independent check of the sinusoid formula through the engine: OADEV of a densely sampled
// W sin(2 pi f0 t) against the continuous closed form. With 1000 samples per period the sampled
// average differs from the continuous one by O((pi f0 dt)^2) ~ 1e-5; the finite record (400
// periods) adds O(1 / periods) ~ 3e-3 at the peak. Allowed 1 %.
TEST(TermAllanVariance, SinusoidMatchesTheEngineOnASampledSine) {
  const double f0 = 0.1, rate_hz = 100.0, w = 2.0;
  const long long n = static_cast<long long>(400 / f0 * rate_hz);
  Eigen::VectorXd y(n);
  for (long long i = 0; i < n; ++i)
    y[i] = w * std::sin(2.0 * 3.141592653589793 * f0 * (i + 0.5) / rate_hz);
  AllanOptions options;
  options.confidence_intervals = false;
  options.grid.kind = TauGridKind::kExplicit;
  options.grid.explicit_m = {100, 200, 371, 500, 700};  // tau = 1 .. 7 s
  const AllanResult r = ComputeAllan(y, rate_hz, options);
  TermParams p;
  p.amplitude = w;
  p.frequency_hz = f0;
  for (size_t k = 0; k < r.table.size(); ++k) {
    const double expected = std::sqrt(TermAllanVariance(Term::kSinusoid, p, r.table.tau_s[k]));
    EXPECT_NEAR(r.table.sigma[k] / expected, 1.0, 0.01) << r.table.tau_s[k];
  }
}

}  // namespace
}  // namespace fogpipe::allan
