// Tests algorithms/filters/butterworth.cpp against closed forms: the sections' transfer function
// evaluated on the unit circle, the analog Butterworth magnitude, the gain of a pure sine, a line
// through the ends, and the spectral GCV against the time-domain residual.
#include "algorithms/filters/butterworth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>

namespace fogpipe::filters {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// |prod_s H_s(e^{i w})|^4: the forward-backward power response from the coefficients.
double CascadePower(const std::vector<Biquad>& sections, double f_hz, double fs) {
  const std::complex<double> z1 = std::polar(1.0, -2.0 * kPi * f_hz / fs);
  std::complex<double> h = 1.0;
  for (const Biquad& s : sections) {
    h *= (s.b0 + s.b1 * z1 + s.b2 * z1 * z1) / (1.0 + s.a1 * z1 + s.a2 * z1 * z1);
  }
  return std::norm(h);
}

TEST(Butterworth, SectionsReproduceTheClosedFormPowerResponse) {
  for (int order : {2, 4}) {
    for (double fc : {0.01, 0.3, 2.0, 20.0}) {
      const auto sections = ButterworthSections(order, fc, 100.0);
      for (double f : {0.0, 0.2 * fc, fc, 1.7 * fc, 5.0 * fc}) {
        if (f >= 50.0) continue;
        const double expected = ZeroPhaseButterworthResponse(order, fc, 100.0, f);
        EXPECT_NEAR(CascadePower(sections, f, 100.0), expected, 1e-9)
            << order << " " << fc << " " << f;
      }
    }
  }
}

TEST(Butterworth, ZeroPhaseResponseIsTheAnalogMagnitudeSquaredWellBelowNyquist) {
  // tan(pi f / fs) = (pi f / fs)(1 + (pi f / fs)^2 / 3 + ...): at f, fc <= fs / 100 the ratio
  // differs from f / fc by < (pi / 100)^2 / 3 = 3.3e-4 relative, u = ratio^2 by 6.6e-4, and
  // |H|^2 = 1 / (1 + u^n) by at most n / 4 x 6.6e-4 (n / 4 bounds |d|H|^2 / d ln u|).
  for (int order : {2, 4}) {
    const double fc = 0.5;  // fs = 100 Hz
    for (double f : {0.05, 0.25, 0.5, 0.8, 1.0}) {
      const double analog = 1.0 / std::sqrt(1.0 + std::pow(f / fc, 2.0 * order));
      EXPECT_NEAR(ZeroPhaseButterworthResponse(order, fc, 100.0, f), analog * analog,
                  order / 4.0 * 6.6e-4);
    }
  }
}

TEST(Butterworth, ASineIsScaledByThePowerResponseAndNotDelayed) {
  const double fs = 10.0, fc = 0.2;
  const Eigen::Index n = 20000;
  for (double f : {0.1, 0.2, 0.4}) {
    Eigen::VectorXd x(n);
    for (Eigen::Index i = 0; i < n; ++i) x[i] = std::sin(2.0 * kPi * f * i / fs);
    const Eigen::VectorXd y = FilterForwardBackward(ButterworthSections(4, fc, fs), x, 150);
    // Least-squares sine and cosine amplitudes over the middle half (away from the ends).
    double ss = 0, sc = 0, s2 = 0, c2 = 0;
    for (Eigen::Index i = n / 4; i < 3 * n / 4; ++i) {
      const double s = std::sin(2.0 * kPi * f * i / fs), c = std::cos(2.0 * kPi * f * i / fs);
      ss += y[i] * s, sc += y[i] * c, s2 += s * s, c2 += c * c;
    }
    const double expected = ZeroPhaseButterworthResponse(4, fc, fs, f);
    EXPECT_NEAR(ss / s2, expected, 1e-6) << f;
    EXPECT_NEAR(sc / c2, 0.0, 1e-6) << f;  // zero phase: no cosine part
  }
}

TEST(Butterworth, ALinePassesThroughBothEndsUnchanged) {
  // The steady-state start fits a constant, not a ramp: a line starts a transient of about
  // slope x group delay (0.002 x ~85 samples = 0.17) that decays as exp(-2 pi zeta fc t), zeta =
  // sin(pi / 8) the slowest pole pair. The odd-reflection pad of 8 cutoff periods (the default,
  // 1600 samples here) leaves 0.17 exp(-2 pi 0.383 x 8) = 7e-10 of it at the first sample.
  const Eigen::Index n = 5000;
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(n, -3.0, 7.0);
  const Eigen::VectorXd y = FilterForwardBackward(ButterworthSections(4, 0.05, 10.0), x, 1600);
  EXPECT_LT((y - x).cwiseAbs().maxCoeff(), 1e-8);
  // A pad of one cutoff period leaves a visible transient: the pad is what removes it.
  const Eigen::VectorXd short_pad =
      FilterForwardBackward(ButterworthSections(4, 0.05, 10.0), x, 200);
  EXPECT_GT((short_pad - x).cwiseAbs().maxCoeff(), 1e-4);
}

TEST(Butterworth, TraceMatchesTheSmootherMatrixBuiltColumnByColumn) {
  // S e_j is the filter's response to a unit impulse at j; tr S = sum_j (S e_j)_j. The spectral
  // trace is that of the circulant on the antisymmetric extension: rows within about one impulse
  // response (3 fs / fc samples) of the ends differ (each diagonal entry lies in [0, 1]), so the
  // traces differ by at most 2 x 3 fs / fc.
  const Eigen::Index n = 400;
  const double fs = 10.0;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g;
  Eigen::VectorXd x(n);
  for (auto& v : x) v = g(rng);
  const ButterworthGcv gcv(x, fs, 4);
  for (double fc : {0.3, 1.0, 3.0}) {
    const auto sections = ButterworthSections(4, fc, fs);
    double trace = 0.0;
    for (Eigen::Index j = 0; j < gcv.samples(); ++j) {
      trace += FilterForwardBackward(sections, Eigen::VectorXd::Unit(gcv.samples(), j),
                                     ButterworthPad(fc, fs))[j];
    }
    double spectral_trace = 0.0;
    gcv.Score(fc, &spectral_trace);
    EXPECT_NEAR(spectral_trace, trace, 2.0 * 3.0 * fs / fc) << fc;
  }
}

TEST(Butterworth, SpectralResidualEqualsTheFilteredResidual) {
  // On the antisymmetric extension the circulant is exactly the forward-backward filter with
  // odd-reflection ends, up to the pad's finite length (transient < 4e-9 of the end slope's lag,
  // see the line test) and the steady-state start: the residual energies agree to 1e-6 relative.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g;
  const double fs = 10.0;
  // 730 samples: an FFT of odd length (L = 1458, the sine transform's n = 729); the others even.
  for (Eigen::Index n : {730, 3000, 4001}) {
    Eigen::VectorXd x(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      x[i] = 3.0 * (i > n / 3) + 0.001 * i + std::sin(2.0 * kPi * 0.02 * i / fs) + 0.5 * g(rng);
    }
    const ButterworthGcv gcv(x, fs, 4);
    const Eigen::VectorXd head = x.head(gcv.samples());
    for (double fc : {0.05, 0.2, 1.0}) {
      double rss = 0.0;
      gcv.Score(fc, nullptr, &rss);
      const Eigen::VectorXd y =
          FilterForwardBackward(ButterworthSections(4, fc, fs), head, ButterworthPad(fc, fs));
      EXPECT_NEAR(rss / (head - y).squaredNorm(), 1.0, 1e-6) << n << " " << fc;
    }
  }
}

TEST(Butterworth, GcvKeepsASlowSineAndRemovesMostNoise) {
  std::mt19937_64 rng(12);
  std::normal_distribution<double> g;
  const Eigen::Index n = 36000;
  const double fs = 10.0;
  Eigen::VectorXd x(n), truth(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    truth[i] = std::sin(2.0 * kPi * 0.005 * i / fs);
    x[i] = truth[i] + g(rng);
  }
  const ButterworthResult r = ZeroPhaseButterworth(x, fs, ButterworthOptions());
  ASSERT_EQ(r.termination, Termination::kSuccess);
  EXPECT_GT(r.cutoff_hz, 0.005);
  EXPECT_LT(r.cutoff_hz, 0.1);
  // White noise of variance 1 passed by a bandwidth B keeps about 2B / fs of its variance: at
  // the cutoff found that is < 0.02, so the error RMS must be well below raw's 1.
  EXPECT_LT(std::sqrt((r.output - truth).squaredNorm() / n), 0.2);
}

/// The textbook forward-backward filter, as scalar reference: the odd-reflection extension built
/// in full, each section run over all of it in turn (transposed direct form II, started in the
/// steady state of its first input), forward, then the same backward, and the middle cut out.
Eigen::VectorXd ReferenceForwardBackward(const std::vector<Biquad>& sections,
                                         const Eigen::VectorXd& x, Eigen::Index pad) {
  const Eigen::Index n = x.size();
  std::vector<double> ext(n + 2 * pad);
  for (Eigen::Index i = 0; i < pad; ++i) {
    ext[i] = 2.0 * x[0] - x[pad - i];
    ext[n + pad + i] = 2.0 * x[n - 1] - x[n - 2 - i];
  }
  for (Eigen::Index i = 0; i < n; ++i) ext[pad + i] = x[i];
  auto run = [&](const Biquad& s, bool forward) {
    const std::size_t m = ext.size();
    auto at = [&](std::size_t i) -> double& { return ext[forward ? i : m - 1 - i]; };
    const double u = at(0);
    double z1 = (1.0 - s.b0) * u, z2 = (s.b2 - s.a2) * u;
    for (std::size_t i = 0; i < m; ++i) {
      const double in = at(i);
      const double y = s.b0 * in + z1;
      z1 = s.b1 * in - s.a1 * y + z2;
      z2 = s.b2 * in - s.a2 * y;
      at(i) = y;
    }
  };
  for (const Biquad& s : sections) run(s, true);
  for (const Biquad& s : sections) run(s, false);
  return Eigen::Map<const Eigen::VectorXd>(ext.data() + pad, n);
}

TEST(Butterworth, ForwardBackwardEqualsTheTextbookFilterOfTheFullExtensionToTheLastBit) {
  std::mt19937_64 rng(91);
  std::normal_distribution<double> normal;
  std::vector<double> work(7, 123.0);  // reused across cases, as the band limiter reuses it
  Eigen::VectorXd out;
  for (const int order : {2, 4}) {
    for (const Eigen::Index n : {2, 3, 17, 1000, 5000}) {
      // Pads from 1 to beyond the record (clamped to n - 1), across the 1024-sample blocks in
      // which the left extension is generated.
      for (const Eigen::Index pad : {1, 5, 999, 1024, 1025, 3000, 9000}) {
        Eigen::VectorXd x(n);
        for (Eigen::Index i = 0; i < n; ++i) x[i] = normal(rng) + 0.01 * static_cast<double>(i);
        const auto sections = ButterworthSections(order, 0.03, 1.0);
        const Eigen::Index clamped = std::clamp<Eigen::Index>(pad, 1, n - 1);
        const Eigen::VectorXd reference = ReferenceForwardBackward(sections, x, clamped);
        FilterForwardBackward(sections, x, pad, &work, &out);
        ASSERT_EQ(out.size(), n);
        for (Eigen::Index i = 0; i < n; ++i) {
          ASSERT_EQ(out[i], reference[i])
              << "order " << order << " n " << n << " pad " << pad << " sample " << i;
        }
        EXPECT_EQ(FilterForwardBackward(sections, x, pad), out);
      }
    }
  }
}

// The right extension's buffer is sized exactly: a grown vector would double its capacity, and
// the band limit's slowest components have pads up to the record length.
TEST(Butterworth, TheWorkBufferHoldsExactlyThePad) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(5000, 0.0, 1.0).array().sin();
  const std::vector<Biquad> sections = ButterworthSections(4, 0.01, 1.0);
  std::vector<double> work(10);
  Eigen::VectorXd out;
  FilterForwardBackward(sections, x, 1000, &work, &out);
  EXPECT_EQ(work.capacity(), 1000u);
  FilterForwardBackward(sections, x, 3001, &work, &out);
  EXPECT_EQ(work.capacity(), 3001u);
  FilterForwardBackward(sections, x, 2000, &work, &out);
  EXPECT_EQ(work.capacity(), 3001u) << "a large enough buffer is reused as it is";
}

}  // namespace
}  // namespace fogpipe::filters
