// Tests of algorithms/allan/deviation.{h,cpp} (and phase.{h,cpp}) against published answers:
// NIST SP 1065 / Riley's 1000-point and 9-point sets, and Stable32 reports on PHASE.DAT and a real
// OCXO record (tests/data/allan-reference, from allantools commit 599dc9e).
#include "algorithms/allan/deviation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "algorithms/allan/phase.h"
#include "tests/algorithms/allan/reference_data.h"
#include "tests/algorithms/allan/simulated_gyro.h"

namespace fogpipe::allan {
namespace {

using testing::ReadStable32Report;

std::vector<double> Deviations(const Eigen::VectorXd& y, Deviation dev, std::vector<long long> m) {
  std::vector<double> v = DeviationVariances(MeanRemovedPhase(y), dev, m);
  for (double& s : v) s = std::sqrt(s);
  return v;
}

struct Published {
  Deviation deviation;
  std::vector<long long> m;
  std::vector<double> sigma;
};

// NIST SP 1065 section 12 (Riley, "The calculation of time domain frequency stability",
// Table III): 7 significant digits, i.e. a rounding of at most 5e-7 relative (half a unit of the
// 7th digit over a mantissa >= 1). We require 1e-6 relative: finer would test the table's
// rounding, not our arithmetic. One entry is evidently truncated rather than rounded
// (HDEV(100) = 3.910860e-02 against the exact 3.91086056e-02, 1.4e-7 relative), which is why the
// check is relative and not "half a unit in the last place".
TEST(Deviation, MatchesTheNist1000PointSetAtThePublishedDigits) {
  const Eigen::VectorXd y = testing::Nbs1000Point();
  ASSERT_NEAR(y[0], 0.5748904732, 1e-10);  // SP 1065 lists the first values
  ASSERT_NEAR(y[1], 0.1841829699, 1e-10);
  const std::vector<Published> published = {
      {Deviation::kAllan, {1, 10, 100}, {2.922319e-01, 9.965736e-02, 3.897804e-02}},
      {Deviation::kOverlappingAllan, {1, 10, 100}, {2.922319e-01, 9.159953e-02, 3.241343e-02}},
      {Deviation::kHadamard, {1, 10, 100}, {2.943883e-01, 1.052754e-01, 3.910860e-02}},
      {Deviation::kOverlappingHadamard, {1, 10, 100}, {2.943883e-01, 9.581083e-02, 3.237638e-02}},
      {Deviation::kModifiedAllan, {1, 10, 100}, {2.922319e-01, 6.172376e-02, 2.170921e-02}},
      {Deviation::kTime, {1, 10, 100}, {1.687202e-01, 3.563623e-01, 1.253382e+00}},
      {Deviation::kTotal, {1, 10, 100}, {2.922319e-01, 9.134743e-02, 3.406530e-02}},
  };
  for (const Published& p : published) {
    const std::vector<double> sigma = Deviations(y, p.deviation, p.m);
    for (size_t k = 0; k < p.m.size(); ++k)
      EXPECT_NEAR(sigma[k], p.sigma[k], 1e-6 * p.sigma[k])
          << ToString(p.deviation) << " m=" << p.m[k];
  }
}

// The NBS14 9-point frequency set (same source, 7 digits, same 1e-6 relative tolerance). The
// published OHDEV(1) = 70.80607 and HDEV(1) = 70.80608 are the same quantity (m = 1 overlaps
// nothing; exact 70.806073...), so one of them is off by a unit in the 7th digit: 1.0e-7 relative.
TEST(Deviation, MatchesTheNbs9PointSet) {
  Eigen::VectorXd y(9);
  y << 892, 809, 823, 798, 671, 644, 883, 903, 677;
  const std::vector<Published> published = {
      {Deviation::kAllan, {1, 2}, {91.22945, 115.8082}},
      {Deviation::kOverlappingAllan, {1, 2}, {91.22945, 85.95287}},
      {Deviation::kHadamard, {1, 2}, {70.80608, 116.7980}},
      {Deviation::kOverlappingHadamard, {1, 2}, {70.80607, 85.61487}},
      {Deviation::kModifiedAllan, {1, 2}, {91.22945, 74.78849}},
      {Deviation::kTime, {1, 2}, {52.67135, 86.35831}},
      {Deviation::kTotal, {1, 2}, {91.22945, 93.90379}},
  };
  for (const Published& p : published) {
    const std::vector<double> sigma = Deviations(y, p.deviation, p.m);
    for (size_t k = 0; k < p.m.size(); ++k)
      EXPECT_NEAR(sigma[k], p.sigma[k], 1e-6 * p.sigma[k])
          << ToString(p.deviation) << " m=" << p.m[k];
  }
}

struct ReportCase {
  const char* file;
  Deviation deviation;
  bool ocxo;  // false: PHASE.DAT
};

// Stable32 prints 5 significant digits: rounding alone is up to 5e-5 relative, so 1e-4 relative
// is the tightest honest tolerance (and the one allantools uses for these files).
TEST(Deviation, MatchesStable32AllTauReports) {
  const std::vector<ReportCase> cases = {
      {"phasedat/phase_dat_oadev.txt", Deviation::kOverlappingAllan, false},
      {"phasedat/phase_dat_adev.txt", Deviation::kAllan, false},
      {"phasedat/phase_dat_hdev.txt", Deviation::kHadamard, false},
      {"phasedat/phase_dat_ohdev.txt", Deviation::kOverlappingHadamard, false},
      {"ocxo/stable32_oadev_alltau.txt", Deviation::kOverlappingAllan, true},
      {"ocxo/stable32_adev_alltau.txt", Deviation::kAllan, true},
      {"ocxo/stable32_hdev_alltau.txt", Deviation::kHadamard, true},
      {"ocxo/stable32_ohdev_alltau.txt", Deviation::kOverlappingHadamard, true},
      {"phasedat/phase_dat_mdev.txt", Deviation::kModifiedAllan, false},
      {"phasedat/phase_dat_tdev.txt", Deviation::kTime, false},
      {"phasedat/phase_dat_totdev.txt", Deviation::kTotal, false},
      {"ocxo/stable32_mdev_alltau.txt", Deviation::kModifiedAllan, true},
      {"ocxo/stable32_tdev_alltau.txt", Deviation::kTime, true},
      {"ocxo/stable32_totdev_alltau.txt", Deviation::kTotal, true},
  };
  const Eigen::VectorXd phasedat = testing::PhaseDatFrequency();
  const Eigen::VectorXd ocxo = testing::OcxoFractionalFrequency();
  ASSERT_EQ(phasedat.size(), 1000);
  ASSERT_EQ(ocxo.size(), 19982);
  for (const ReportCase& c : cases) {
    const auto rows = ReadStable32Report(c.file);
    ASSERT_GT(rows.size(), 100u) << c.file;
    const Eigen::VectorXd& y = c.ocxo ? ocxo : phasedat;
    std::vector<long long> m;
    for (const auto& row : rows) m.push_back(row.m);
    const std::vector<double> sigma = Deviations(y, c.deviation, m);
    for (size_t k = 0; k < rows.size(); ++k) {
      EXPECT_NEAR(sigma[k], rows[k].sigma, 1e-4 * rows[k].sigma) << c.file << " m=" << m[k];
      EXPECT_EQ(DifferenceCount(c.deviation, y.size(), m[k]), rows[k].count) << c.file;
    }
  }
}

// The total variance has n - 1 terms at every factor (the reflections supply the missing ends);
// its limit m <= (n - 1) / 2 is Stable32's (tau up to T / 2), checked in the all-tau reports.
// MDEV's S_j spans only 3m - 1 phase steps, so a term can exist one factor beyond T / 3; we stop
// at SP 1065's tau <= T / 3 as for the Hadamard variance.
TEST(Deviation, MaxAveragingFactorKeepsAtLeastOneDifference) {
  for (Deviation dev : AllDeviations()) {
    for (long long n : {2, 3, 7, 1000, 19982}) {
      const long long max_m = MaxAveragingFactor(dev, n);
      if (max_m < 1) continue;
      EXPECT_GE(DifferenceCount(dev, n, max_m), 1) << ToString(dev) << " n=" << n;
      if (dev != Deviation::kTotal && !IsModified(dev)) {
        EXPECT_LT(DifferenceCount(dev, n, max_m + 1), 1) << ToString(dev) << " n=" << n;
      }
    }
  }
  EXPECT_EQ(MaxAveragingFactor(Deviation::kTotal, 1000), 499);
  EXPECT_EQ(MaxAveragingFactor(Deviation::kModifiedAllan, 1000), 333);
}

TEST(Deviation, NamesRoundTripAndOnlyAllanTablesTakeTheIeeeModel) {
  for (Deviation dev : AllDeviations()) {
    Deviation parsed = Deviation::kHadamard;
    ASSERT_TRUE(ParseDeviation(ToString(dev), &parsed)) << ToString(dev);
    EXPECT_EQ(parsed, dev);
    EXPECT_EQ(IeeeModelApplies(dev),
              dev == Deviation::kOverlappingAllan || dev == Deviation::kAllan)
        << ToString(dev);
  }
  Deviation unused;
  EXPECT_FALSE(ParseDeviation("theoh", &unused));
  EXPECT_EQ(AllDeviations().size(), 7u);
}

// Plain scalar references, written from the definitions in NIST SP 1065 (eqs. 14, 15 and 25)
// with no prefix sum, no blocks and no shortcut at the ends, in long double on the plain running
// sum of the rate (no mean removal): what the blocked sweeps are held against.
std::vector<long double> ReferencePhases(const Eigen::VectorXd& y) {
  long double mean = 0.0L;
  for (Eigen::Index i = 0; i < y.size(); ++i) mean += y[i];
  mean /= y.size();
  std::vector<long double> x(y.size() + 1, 0.0L);
  for (Eigen::Index i = 0; i < y.size(); ++i)
    x[i + 1] = x[i] + (static_cast<long double>(y[i]) - mean);
  return x;
}

// Mod sigma^2 = sum_j [sum_{i=j}^{j+m-1} (x_{i+2m} - 2 x_{i+m} + x_i)]^2 / (2 m^4 (N - 3m + 1)).
long double ReferenceMvar(const std::vector<long double>& x, long long m) {
  const long long big_n = static_cast<long long>(x.size());
  const long long count = big_n - 3 * m + 1;
  long double sum = 0.0L;
  for (long long j = 0; j < count; ++j) {
    long double s = 0.0L;
    for (long long i = j; i < j + m; ++i) s += x[i + 2 * m] - 2.0L * x[i + m] + x[i];
    sum += s * s;
  }
  const long double mm = m;
  return sum / (2.0L * mm * mm * mm * mm * count);
}

// SP 1065 eq. 25 with the extended sequence built explicitly: x*_{1-j} = 2 x_1 - x_{1+j} and
// x*_{N+j} = 2 x_N - x_{N-j}, j = 1 .. N - 2 (1-based), then all centres i = 2 .. N - 1.
long double ReferenceTotvar(const std::vector<long double>& x, long long m) {
  const long long big_n = static_cast<long long>(x.size());
  std::vector<long double> ext;
  for (long long j = big_n - 2; j >= 1; --j) ext.push_back(2.0L * x[0] - x[j]);
  const long long offset = static_cast<long long>(ext.size());
  ext.insert(ext.end(), x.begin(), x.end());
  for (long long j = 1; j <= big_n - 2; ++j) ext.push_back(2.0L * x[big_n - 1] - x[big_n - 1 - j]);
  long double sum = 0.0L;
  for (long long i = 1; i <= big_n - 2; ++i) {
    const long double d = ext[offset + i - m] - 2.0L * ext[offset + i] + ext[offset + i + m];
    sum += d * d;
  }
  const long double mm = m;
  return sum / (2.0L * mm * mm * (big_n - 2));
}

// Each fast value against its reference. Double sums of ~4000 terms are good to ~1e-13
// relative here (the noise has no term that makes S_j cancel by more than ~1e3); 1e-10 leaves
// room and still catches any slip in a formula or an end term (>= 1e-4).
TEST(Deviation, ModifiedTimeAndTotalEqualPlainScalarReferences) {
  testing::GyroTruth truth;
  truth.n_rad_sqrt_s = 1.0;
  truth.k_rad_s_sqrt_s = 0.01;
  truth.q_rad = 0.3;
  Eigen::VectorXd y = testing::SimulateGyro(truth, 4099, 1.0, 21);
  y.array() += 50.0;  // a bias many times the noise, as a gyro has
  const std::vector<long double> x = ReferencePhases(y);
  const std::vector<long long> m = {1, 2, 3, 4, 7, 8, 16, 33, 64, 100, 128, 256, 512, 1000, 1365};
  const std::vector<double> mdev = Deviations(y, Deviation::kModifiedAllan, m);
  const std::vector<double> tdev = Deviations(y, Deviation::kTime, m);
  std::vector<long long> m_total = m;
  m_total.push_back(2048);  // beyond N / 3: more reflected terms than ordinary ones
  m_total.push_back(MaxAveragingFactor(Deviation::kTotal, y.size()));
  const std::vector<double> totdev = Deviations(y, Deviation::kTotal, m_total);
  for (size_t k = 0; k < m.size(); ++k) {
    const double ref = static_cast<double>(std::sqrt(ReferenceMvar(x, m[k])));
    EXPECT_NEAR(mdev[k], ref, 1e-10 * ref) << "mdev m=" << m[k];
    const double ref_t = ref * m[k] / std::sqrt(3.0);
    EXPECT_NEAR(tdev[k], ref_t, 1e-10 * ref_t) << "tdev m=" << m[k];
  }
  for (size_t k = 0; k < m_total.size(); ++k) {
    const double ref = static_cast<double>(std::sqrt(ReferenceTotvar(x, m_total[k])));
    EXPECT_NEAR(totdev[k], ref, 1e-10 * ref) << "totdev m=" << m_total[k];
  }
}

// The window sums P_{j+m} - P_j of the phase's prefix sum P must keep their digits however large
// P grows. Random-walk plus white rate noise, 1e5 samples on a 1e6 bias: the phase reaches ~3e7
// and P ~3e12, while S_j at m = 1 (a first difference of the rate) is ~2. A plain double prefix
// sum would put a rounding of P (~3e-4) into every S_j, ~1e-6 of the variance after averaging;
// the double-double one leaves only the phase's own rounding (~3e-9 per S_j, ~1e-11 of the
// variance). The reference is the long double definition; 1e-9 relative separates the two.
TEST(Deviation, ModifiedVarianceKeepsFullPrecisionOnALongWanderingRecord) {
  testing::GyroTruth walk;
  walk.k_rad_s_sqrt_s = 1.0;
  walk.n_rad_sqrt_s = 1.0;
  Eigen::VectorXd y = testing::SimulateGyro(walk, 100003, 1.0, 33);
  y.array() += 1e6;
  const std::vector<long double> x = ReferencePhases(y);
  const std::vector<long long> m = {1, 2, 5, 16};
  const std::vector<double> mdev = Deviations(y, Deviation::kModifiedAllan, m);
  for (size_t k = 0; k < m.size(); ++k) {
    const double ref = static_cast<double>(std::sqrt(ReferenceMvar(x, m[k])));
    EXPECT_NEAR(mdev[k], ref, 1e-9 * ref) << "m=" << m[k];
  }
}

// A constant rate ramp r: phase r t^2 / 2, so the Allan variance is r^2 tau^2 / 2 exactly
// (IEEE 952 Annex C) while every third difference, hence the Hadamard variance, vanishes.
TEST(Deviation, HadamardIsBlindToARateRampThatAllanSees) {
  const double ramp = 1e-3;
  Eigen::VectorXd y(4000);
  for (Eigen::Index i = 0; i < y.size(); ++i) y[i] = 5.0 + ramp * (i + 0.5);
  const std::vector<long long> m = {1, 10, 100, 1000};
  const std::vector<double> hadamard = Deviations(y, Deviation::kOverlappingHadamard, m);
  const std::vector<double> allan = Deviations(y, Deviation::kOverlappingAllan, m);
  for (size_t k = 0; k < m.size(); ++k) {
    const double tau = static_cast<double>(m[k]);
    EXPECT_NEAR(allan[k], ramp * tau / std::sqrt(2.0), 1e-9 * ramp * tau) << m[k];
    // Rounding of the O(n^2 ramp) phase leaves ~1e-16 * 4000^2 * 1e-3 / tau in the differences.
    EXPECT_LT(hadamard[k], 1e-9) << m[k];
  }
}

// The sweep's chunks are shared among threads but added in a fixed order: every overlapping kind
// gives bit-identical values for 1, 2 and 3 threads on a record of several chunks.
TEST(Deviation, ValuesDoNotDependOnTheThreadCount) {
  testing::GyroTruth truth;
  truth.n_rad_sqrt_s = 1.0;
  truth.k_rad_s_sqrt_s = 1e-3;
  const Eigen::VectorXd y = testing::SimulateGyro(truth, 1700000, 1.0, 34);
  const Eigen::VectorXd phase = MeanRemovedPhase(y);
  const std::vector<long long> m = {1, 7, 64, 1000, 30000, 400000};
  for (Deviation d : {Deviation::kOverlappingAllan, Deviation::kOverlappingHadamard,
                      Deviation::kModifiedAllan, Deviation::kTotal}) {
    const std::vector<double> one = DeviationVariances(phase, d, m, 1);
    for (int threads : {2, 3})
      EXPECT_EQ(DeviationVariances(phase, d, m, threads), one) << ToString(d);
  }
}

// The compensated cumulative sum keeps a huge bias from eating the digits of the noise: a 1e6 bias
// on unit noise must give the same deviation as the noise alone.
TEST(Phase, MeanRemovalKeepsDeviationsIndependentOfALargeBias) {
  Eigen::VectorXd y = testing::Nbs1000Point();
  const std::vector<long long> m = {1, 10, 100};
  const std::vector<double> plain = Deviations(y, Deviation::kOverlappingAllan, m);
  y.array() += 1e6;
  const std::vector<double> biased = Deviations(y, Deviation::kOverlappingAllan, m);
  // The biased samples themselves are rounded to ulp(1e6) = 1.2e-10 (relative 4e-10 of sigma).
  for (size_t k = 0; k < m.size(); ++k) EXPECT_NEAR(biased[k], plain[k], 1e-8 * plain[k]);
}

// The running sum is computed in four parts side by side and the parts shifted by the totals
// before them (phase.cpp): every value must still be the running sum of the mean-removed rate to
// within a few roundings of the largest phase value, checked against long double (64-bit mantissa,
// 2^11 times finer) on a length that is not a multiple of 4, with a bias 1e6 times the noise and a
// slow drift so the phase wanders far from 0. The mean is the one the function uses: the double
// nearest the exact sum (which long double resolves far below ulp(1e11)), divided by n; each
// y - mean is then exact (Sterbenz), so only the running sum is under test.
TEST(Phase, TheRunningSumIsExactToAFewRoundingsOnLongSeries) {
  const Eigen::Index n = 100003;
  testing::GyroTruth white;
  white.n_rad_sqrt_s = 1.0;
  Eigen::VectorXd y = testing::SimulateGyro(white, n, 1.0, 5);
  for (Eigen::Index k = 0; k < n; ++k) y[k] += 1e6 + 1e-3 * std::sin(1e-4 * k);
  const Eigen::VectorXd x = MeanRemovedPhase(y);
  long double sum = 0.0L;
  for (Eigen::Index k = 0; k < n; ++k) sum += y[k];
  const double mean = static_cast<double>(sum) / static_cast<double>(n);
  long double running = 0.0L, largest = 0.0L;
  double worst = 0.0;
  ASSERT_EQ(x.size(), n + 1);
  for (Eigen::Index k = 0; k < n; ++k) {
    running += static_cast<long double>(y[k] - mean);
    largest = std::max(largest, std::fabs(running));
    worst = std::max(worst, static_cast<double>(std::fabs(x[k + 1] - running)));
  }
  // A few roundings (ulp = 2^-52 relative) of the largest |phase| (~180 here).
  EXPECT_LE(worst, 8.0 * std::ldexp(static_cast<double>(largest), -52))
      << "largest |phase| " << static_cast<double>(largest);
}

TEST(OverlappingBlockSums4, EachLagHasTheBitsOfItsEigenSumAtEveryLengthAndStart) {
  // The sweep's four-lag kernel against the Eigen expressions it replaces, to the last bit:
  // second (Allan) and third (Hadamard) differences, lags 1 to 37, every length 0-100 and several
  // starts, on values spread over many magnitudes so that another order of the additions rounds
  // differently.
  std::mt19937_64 rng(1065);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-20, 20);
  std::vector<double> x(512);
  for (double& v : x) v = std::ldexp(mantissa(rng), exponent(rng));
  auto bits = [](double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof(b));
    return b;
  };
  using Segment = Eigen::Map<const Eigen::VectorXd>;
  const long long lag_sets[][4] = {{1, 2, 4, 8}, {3, 5, 7, 37}, {16, 1, 16, 2}};
  for (const int d : {2, 3}) {
    for (const auto& m : lag_sets) {
      for (Eigen::Index len = 0; len <= 100; ++len) {
        for (const Eigen::Index begin : {0, 1, 2, 3, 5}) {
          double sums[4];
          internal::OverlappingBlockSums4(x.data(), d, m, begin, len, sums);
          for (int k = 0; k < 4; ++k) {
            const Segment x0(x.data() + begin, len), x1(x.data() + begin + m[k], len),
                x2(x.data() + begin + 2 * m[k], len), x3(x.data() + begin + 3 * m[k], len);
            const double eigen = d == 2 ? (x2 - 2.0 * x1 + x0).squaredNorm()
                                        : (x3 - 3.0 * x2 + 3.0 * x1 - x0).squaredNorm();
            ASSERT_EQ(bits(sums[k]), bits(eigen))
                << "d " << d << " m " << m[k] << " len " << len << " begin " << begin;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace fogpipe::allan
