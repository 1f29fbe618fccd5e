// Tests algorithms/method/preprocess.cpp on signals whose truth is known by construction.
#include "algorithms/method/preprocess.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <utility>
#include <vector>

namespace fogpipe::method {
namespace {

// Gaussian samples by Box-Muller from an explicitly seeded mt19937_64 (portable, deterministic).
Eigen::VectorXd Gaussian(int n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto uniform = [&rng]() { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; i += 2) {
    const double r = std::sqrt(-2.0 * std::log(uniform())), t = 2.0 * M_PI * uniform();
    x[i] = sigma * r * std::cos(t);
    if (i + 1 < n) x[i + 1] = sigma * r * std::sin(t);
  }
  return x;
}

TEST(Preprocess, DropsTheStartAndRemovesTheMean) {
  Eigen::VectorXd x = Gaussian(1000, 1.0, 1);
  x.head(100).array() += 50.0;  // start-up transient
  x.array() += 3.0;
  PreprocessOptions options;
  options.drop_start_s = 10.0;  // 100 samples at 10 Hz
  const Preprocessed p = Preprocess(x, 10.0, options);
  ASSERT_EQ(p.summary.termination, Termination::kSuccess) << p.summary.message;
  EXPECT_EQ(p.summary.dropped_samples, 100);
  EXPECT_EQ(p.signal.size(), 900);
  EXPECT_NEAR(p.signal.mean(), 0.0, 1e-14);
  // Kept samples are N(3, 1): the removed mean is within 4 standard errors of 3.
  EXPECT_NEAR(p.mean_removed, 3.0, 4.0 / std::sqrt(900.0));
}

TEST(Preprocess, ReplacesPlantedOutliersAndOnlyThem) {
  Eigen::VectorXd x = Gaussian(20000, 1.0, 2);
  const std::vector<long long> planted = {17, 5000, 12345, 19990};
  for (long long i : planted) x[i] += 40.0;  // 40 sigma gross errors
  const Preprocessed p = Preprocess(x, 1.0, PreprocessOptions());
  ASSERT_EQ(p.summary.termination, Termination::kSuccess);
  // A Gaussian sample exceeds 5 (local, estimated) sigma with probability ~1e-6 per sample, so at
  // most a couple of false alarms are expected in 2e4 samples; the planted ones must all be found.
  for (long long i : planted) {
    EXPECT_NE(std::find(p.outlier_indices.begin(), p.outlier_indices.end(), i),
              p.outlier_indices.end())
        << i;
  }
  EXPECT_LE(p.outlier_indices.size(), planted.size() + 2);
  EXPECT_LT(p.signal.cwiseAbs().maxCoeff(), 8.0);
}

// The Hampel rule written out directly: each window's median by a full sort of a copy, the scale
// per block as preprocess.h states it. An independent statement of the rule that the sliding
// median of preprocess.cpp must reproduce exactly, ties and signed zeros included.
std::vector<std::pair<long long, double>> HampelByDefinition(const Eigen::VectorXd& x, int h,
                                                             double threshold, int block) {
  const long long n = x.size();
  auto median_of = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    return v.size() % 2 == 1 ? v[m] : 0.5 * (v[m - 1] + v[m]);
  };
  std::vector<double> median(n);
  for (long long k = 0; k < n; ++k) {
    const long long lo = std::max(0LL, k - h), hi = std::min(n - 1, k + h);
    median[k] = median_of(std::vector<double>(x.data() + lo, x.data() + hi + 1));
  }
  std::vector<std::pair<long long, double>> replaced;
  for (long long start = 0; start < n;) {
    long long end = std::min(n, start + block);
    if (n - end < block / 2) end = n;
    std::vector<double> deviation;
    for (long long k = start; k < end; ++k) deviation.push_back(std::abs(x[k] - median[k]));
    const double limit = threshold * 1.482602218505602 * median_of(deviation);
    for (long long k = start; k < end; ++k)
      if (limit > 0.0 && std::abs(x[k] - median[k]) > limit) replaced.emplace_back(k, median[k]);
    start = end;
  }
  return replaced;
}

TEST(Preprocess, ReplacesExactlyTheSamplesTheHampelRuleNamesByItsWindowMedians) {
  // Counts of a coarse quantizer (many ties, signed zeros) with gross errors every ~50 samples,
  // at lengths below, at and just above one window and well beyond.
  for (const int n : {8, 10, 11, 12, 13, 2000, 20011}) {
    Eigen::VectorXd x = Gaussian(n, 1.0, 300 + n);
    for (int i = 0; i < n; ++i) {
      x[i] = std::round(2.0 * x[i]) * (i % 3 == 0 ? -0.5 : 0.5);  // -0.0 and +0.0 both occur
      if (i % 53 == 7) x[i] += (i % 2 ? 30.0 : -30.0);
    }
    PreprocessOptions options;
    options.hampel_scale_block = 100;
    options.min_samples = 8;
    const Preprocessed p = Preprocess(x, 1.0, options);
    ASSERT_EQ(p.summary.termination, Termination::kSuccess) << n << " " << p.summary.message;
    const auto expected = HampelByDefinition(x, options.hampel_half_window,
                                             options.hampel_threshold, options.hampel_scale_block);
    ASSERT_EQ(p.outlier_indices.size(), expected.size()) << n;
    for (std::size_t j = 0; j < expected.size(); ++j) {
      const long long k = expected[j].first;
      EXPECT_EQ(p.outlier_indices[j], k) << n;
      // The stored signal has its mean removed: one rounding of a value of order 1 (1e-12).
      EXPECT_NEAR(p.signal[k] + p.mean_removed, expected[j].second, 1e-12) << n << " " << k;
    }
  }
}

TEST(Preprocess, InPartsReplacesTheSameSamplesByTheSameMediansAsOnePass) {
  // Lengths of 2, 3 and 17 parts of the 65536-sample minimum (17 is above the 16-part limit),
  // even and odd scale blocks; the same coarse counts with signed zeros and gross errors as above.
  // The last 500 samples are 20 times louder, so which block they fall in decides which samples
  // are outliers: 131631 = 131.5 blocks of 1001 exactly, where a tail of half a block (500) is
  // not yet absorbed into the block before it. The parts run in reverse order, as a schedule may.
  const ForEach reversed = [](int n, const std::function<void(int)>& body) {
    for (int i = n - 1; i >= 0; --i) body(i);
  };
  for (const int n : {2 * 65536 + 1, 131631, 3 * 65536 + 777, 17 * 65536 + 5}) {
    for (const int block : {100, 1001}) {
      Eigen::VectorXd x = Gaussian(n, 1.0, 900 + n);
      for (int i = 0; i < n; ++i) {
        x[i] = std::round(2.0 * x[i]) * (i % 3 == 0 ? -0.5 : 0.5) * (i >= n - 500 ? 20.0 : 1.0);
        if (i % 53 == 7) x[i] += (i % 2 ? 30.0 : -30.0);
      }
      PreprocessOptions options;
      options.hampel_scale_block = block;
      const Preprocessed one = Preprocess(x, 1.0, options);
      options.for_each = reversed;
      const Preprocessed parts = Preprocess(x, 1.0, options);
      ASSERT_EQ(one.summary.termination, Termination::kSuccess) << one.summary.message;
      ASSERT_EQ(parts.summary.termination, Termination::kSuccess) << parts.summary.message;
      EXPECT_EQ(parts.outlier_indices, one.outlier_indices) << n << " " << block;
      EXPECT_EQ(parts.mean_removed, one.mean_removed) << n << " " << block;
      // Equal as numbers (a zero median may carry either sign, see LocalMediansOf).
      EXPECT_TRUE((parts.signal.array() == one.signal.array()).all()) << n << " " << block;
      const auto expected =
          HampelByDefinition(x, options.hampel_half_window, options.hampel_threshold, block);
      ASSERT_EQ(parts.outlier_indices.size(), expected.size()) << n << " " << block;
      for (std::size_t j = 0; j < expected.size(); ++j)
        ASSERT_EQ(parts.outlier_indices[j], expected[j].first) << n << " " << block;
    }
  }
}

TEST(Preprocess, RejectsANonFiniteSampleNamingItsIndex) {
  Eigen::VectorXd x = Gaussian(200, 1.0, 5);
  x[150] = std::nan("");
  PreprocessOptions options;
  options.drop_start_s = 10.0;
  const Preprocessed p = Preprocess(x, 1.0, options);
  EXPECT_EQ(p.summary.termination, Termination::kNumericalFailure);
  EXPECT_NE(p.summary.message.find("index 150"), std::string::npos) << p.summary.message;
}

TEST(Preprocess, RejectsAConstantSignalAndTooFewSamples) {
  Preprocessed p = Preprocess(Eigen::VectorXd::Constant(500, 2.5), 1.0, PreprocessOptions());
  EXPECT_EQ(p.summary.termination, Termination::kNumericalFailure);
  EXPECT_NE(p.summary.message.find("constant"), std::string::npos);
  PreprocessOptions options;
  options.drop_start_s = 480.0;
  p = Preprocess(Gaussian(500, 1.0, 3), 1.0, options);
  EXPECT_EQ(p.summary.termination, Termination::kInsufficientData);
  EXPECT_NE(p.summary.message.find("too few samples"), std::string::npos);
}

TEST(Preprocess, WindowedMeanAndVarianceFollowAStepInLevelAndSpread) {
  Eigen::VectorXd x = Gaussian(4000, 1.0, 4);
  x.tail(2000) = 3.0 * x.tail(2000).array() + 10.0;
  PreprocessOptions options;
  options.window_s = 100.0;
  options.remove_outliers = false;
  const Preprocessed p = Preprocess(x, 1.0, options);
  ASSERT_EQ(p.window_mean.size(), 40);
  // Window means of 100 N(0,1) / N(10,9) samples: standard errors 0.1 and 0.3; 6 of them bound all
  // 40 windows with overwhelming probability. Variances: relative standard error sqrt(2/99).
  for (int w = 0; w < 40; ++w) {
    const bool second = w >= 20;
    EXPECT_NEAR(p.window_mean[w], second ? 10.0 : 0.0, second ? 1.8 : 0.6);
    EXPECT_NEAR(p.window_variance[w] / (second ? 9.0 : 1.0), 1.0, 6.0 * std::sqrt(2.0 / 99.0));
  }
}

TEST(Preprocess, TheNoteStatesWhatWasDroppedAndReplacedAndThatAllanReadsTheStoredRecording) {
  const std::string note = PreprocessingNote(500, 1243);
  EXPECT_NE(note.find("500 samples dropped at the start"), std::string::npos) << note;
  EXPECT_NE(note.find("1243 outliers replaced"), std::string::npos) << note;
  EXPECT_NE(note.find("`fogpipe allan` analyses the recording as stored"), std::string::npos)
      << note;
}

}  // namespace
}  // namespace fogpipe::method
