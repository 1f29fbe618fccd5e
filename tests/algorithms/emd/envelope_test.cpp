#include "algorithms/emd/envelope.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "algorithms/emd/cubic_spline.h"

namespace fogpipe::emd {
namespace {

// Upper and lower envelopes that are cubics: not-a-knot splines reproduce them exactly.
double Upper(double t) { return 3.0 + 0.02 * t - 4e-4 * t * t + 2e-6 * t * t * t; }
double Lower(double t) { return -2.0 + 0.01 * t + 3e-4 * t * t - 1e-6 * t * t * t; }

// A zigzag whose maxima lie on Upper at t = 3, 13, 23, ... and minima on Lower at t = 8, 18, ...:
// straight lines between them, so the extrema are exactly these samples.
std::vector<double> Zigzag(int n) {
  std::vector<int> knots;
  for (int t = 3; t < n - 1; t += 5) knots.push_back(t);
  std::vector<double> x(n);
  auto value = [&](size_t k) { return k % 2 == 0 ? Upper(knots[k]) : Lower(knots[k]); };
  for (int i = 0; i < n; ++i) {
    size_t k = 0;
    while (k + 1 < knots.size() && knots[k + 1] <= i) ++k;
    // Outside the knots, reflect the neighbouring segment so the end knots stay extrema.
    if (i < knots[0]) {
      const double slope = (value(1) - value(0)) / (knots[1] - knots[0]);
      x[i] = value(0) + slope * (knots[0] - i);
    } else if (k + 1 == knots.size()) {
      const double slope = (value(k) - value(k - 1)) / (knots[k] - knots[k - 1]);
      x[i] = value(k) - slope * (i - knots[k]);
    } else {
      x[i] = value(k) + (value(k + 1) - value(k)) * (i - knots[k]) / (knots[k + 1] - knots[k]);
    }
  }
  return x;
}

// Knots and not-a-knot moments of both envelopes of x, without mirrored ends: outside the knots
// the end pieces extend the cubics themselves.
struct Envelopes {
  explicit Envelopes(const std::vector<double>& x) {
    const int n = static_cast<int>(x.size());
    upper.Reserve(n);
    lower.Reserve(n);
    FindExtrema(x.data(), n, &upper, &lower);
    std::vector<double> work(n + 4);
    SolveMoments(upper, SplineKind::kNotAKnot, upper.moments(), work.data());
    SolveMoments(lower, SplineKind::kNotAKnot, lower.moments(), work.data());
  }
  EnvelopeKnots upper, lower;
};

TEST(Envelope, SubtractsTheMeanOfCubicEnvelopesExactly) {
  const int n = 200;
  std::vector<double> x = Zigzag(n);
  const std::vector<double> original = x;
  Envelopes env(x);
  const SiftStatistics stats =
      SubtractEnvelopeMean(x.data(), n, env.upper, env.lower, SiftStatisticsKind::kCauchy);
  double sum_m2 = 0.0, sum_h2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double mean = 0.5 * (Upper(i) + Lower(i));
    // Values of order 5 through splines with knots 10 apart: rounding of order 1e-14.
    EXPECT_NEAR(x[i], original[i] - mean, 1e-12) << "sample " << i;
    sum_m2 += mean * mean;
    sum_h2 += original[i] * original[i];
  }
  EXPECT_NEAR(stats.sum_mean_sq, sum_m2, 1e-10 * sum_m2);
  EXPECT_NEAR(stats.sum_input_sq, sum_h2, 1e-12 * sum_h2);
}

TEST(Envelope, CountsRillingExceedancesOfMeanOverAmplitude) {
  const int n = 200;
  std::vector<double> x = Zigzag(n);
  Envelopes env(x);
  // sigma = |m| / a at every sample; the thresholds are put midway between two consecutive sorted
  // values (at the 30 % and 80 % points) so that rounding cannot move a sample across them.
  std::vector<double> sigma(n);
  for (int i = 0; i < n; ++i) {
    sigma[i] = std::abs(Upper(i) + Lower(i)) / std::abs(Upper(i) - Lower(i));
  }
  std::vector<double> sorted = sigma;
  std::sort(sorted.begin(), sorted.end());
  const double theta1 = 0.5 * (sorted[60] + sorted[61]);
  const double theta2 = 0.5 * (sorted[160] + sorted[161]);
  ASSERT_GT(sorted[61] - sorted[60], 1e-9);
  ASSERT_GT(sorted[161] - sorted[160], 1e-9);
  const int64_t over1 = n - 61, over2 = n - 161;
  const SiftStatistics stats = SubtractEnvelopeMean(x.data(), n, env.upper, env.lower,
                                                    SiftStatisticsKind::kRilling, theta1, theta2);
  EXPECT_EQ(stats.num_over_theta1, over1);
  EXPECT_EQ(stats.num_over_theta2, over2);
}

// Knots and moments of the envelopes of white noise (dense knots, mirrored ends).
struct NoiseEnvelopes {
  explicit NoiseEnvelopes(const std::vector<double>& x) {
    const int n = static_cast<int>(x.size());
    upper.Reserve(n);
    lower.Reserve(n);
    FindExtrema(x.data(), n, &upper, &lower);
    MirrorEnds(x.data(), n, &upper, &lower);
    std::vector<double> work(n + 4);
    SolveMoments(upper, SplineKind::kNotAKnot, upper.moments(), work.data());
    SolveMoments(lower, SplineKind::kNotAKnot, lower.moments(), work.data());
  }
  EnvelopeKnots upper, lower;
};

// Runs the bodies last to first: a schedule unlike the serial one, so that a part that read a
// knot its left neighbour already overwrote would show.
void BackwardForEach(int n, const std::function<void(int)>& body) {
  for (int i = n - 1; i >= 0; --i) body(i);
}

TEST(Envelope, PassInPartsIsBitIdenticalToTheSerialPassWhateverThePartsAndTheOrder) {
  const int n = 10007;
  std::vector<double> x(n);
  uint64_t state = 12345;
  for (double& v : x) {  // xorshift noise: a knot every 1.5 samples on average
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    v = static_cast<double>(state >> 11) * 0x1.0p-53 - 0.5;
  }
  // kCauchy: the parts function runs the serial pass itself (its sums must not be reordered).
  for (SiftStatisticsKind kind :
       {SiftStatisticsKind::kNone, SiftStatisticsKind::kRilling, SiftStatisticsKind::kCauchy}) {
    std::vector<double> serial = x;
    NoiseEnvelopes se(serial);
    se.upper.RebindSignal(serial.data());
    se.lower.RebindSignal(serial.data());
    const SiftStatistics a =
        SubtractEnvelopeMean(serial.data(), n, se.upper, se.lower, kind, 0.05, 0.5);
    for (int parts : {1, 2, 3, 7, 64}) {
      std::vector<double> h = x;
      NoiseEnvelopes pe(h);
      pe.upper.RebindSignal(h.data());
      pe.lower.RebindSignal(h.data());
      const SiftStatistics b = SubtractEnvelopeMeanInParts(h.data(), n, pe.upper, pe.lower, kind,
                                                           0.05, 0.5, parts, BackwardForEach);
      EXPECT_EQ(h, serial) << "parts " << parts;
      EXPECT_EQ(a.num_over_theta1, b.num_over_theta1) << "parts " << parts;
      EXPECT_EQ(a.num_over_theta2, b.num_over_theta2) << "parts " << parts;
      EXPECT_EQ(a.sum_mean_sq, b.sum_mean_sq) << "parts " << parts;
      EXPECT_EQ(a.sum_input_sq, b.sum_input_sq) << "parts " << parts;
    }
  }
}

}  // namespace
}  // namespace fogpipe::emd
