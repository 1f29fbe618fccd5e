// Calibration of FitNoiseTerms' standard errors and significance over many simulated records
// (simulated_gyro.h: each term from its own seeded stream; truth known). Two claims:
//   (1) for every term present in the truth, z = (estimate - truth) / SE has standard deviation
//       in [0.8, 1.25];
//   (2) a term absent from the truth is significant (theta / se(theta) > 2) in <= 5 % of records.
// The CI tests use 80 records per scenario (seeds 20000-24079); the study behind
// docs/allan-noise-fit.md is the DISABLED_ test with 250 records per scenario on other seeds
// (40000+), and 1000 navigation records on held-out seeds (60000+) for Q's false alarms. Run them
// with
//   allan_noise_fit_calibration_test --gtest_also_run_disabled_tests --gtest_filter=*Study*
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/noise_fit.h"
#include "tests/algorithms/allan/simulated_gyro.h"

namespace fogpipe::allan {
namespace {

struct Scenario {
  const char* name;
  testing::GyroTruth truth;
  long long samples;
  double rate_hz;
};

// Each scenario at 10 Hz, 2^18 samples (7.3 h), octave grid. Amplitudes put the crossovers
// inside the tau range (see docs/allan-noise-fit.md): white only; all five terms (Q/N at 0.3 s,
// N/B at 10 s, B/K at 300 s, K/R at 3000 s); navigation grade N + B + K (N/B at 30 s, B/K at
// 1000 s); Q + B + K without N (Q/B at 17 s, B/K at 300 s), whose curve passes through N's -1/2
// slope between Q and B, so N has a slope read-off but no term. B is sampled as an integrating gyro
// outputs it (simulated_gyro.h), whose Allan variance is the IEEE floor (2 ln2 / pi) B^2 at every
// m; Kasdin's discrete filter exceeds it at m <= 8, which biased Q upward
// (SimulatedBiasInstabilityHasTheIeeeFloorAtShortTau).
std::vector<Scenario> Scenarios() {
  std::vector<Scenario> s(4);
  s[0].name = "white";
  s[0].truth.n_rad_sqrt_s = 1e-5;
  s[1].name = "five terms";
  s[1].truth.q_rad = 3.16e-6;
  s[1].truth.n_rad_sqrt_s = 1e-5;
  s[1].truth.b_rad_s = 4.76e-6;
  s[1].truth.k_rad_s_sqrt_s = 3.16e-7;
  s[1].truth.r_rad_s2 = 4.7e-9;
  s[2].name = "navigation N+B+K";
  s[2].truth.n_rad_sqrt_s = 1e-6;
  s[2].truth.b_rad_s = 2.75e-7;
  s[2].truth.k_rad_s_sqrt_s = 1e-8;
  s[3].name = "Q+B+K without N";
  s[3].truth.q_rad = 3.16e-5;
  s[3].truth.b_rad_s = 4.76e-6;
  s[3].truth.k_rad_s_sqrt_s = 3.16e-7;
  for (Scenario& x : s) {
    x.samples = 1 << 18, x.rate_hz = 10.0;
    x.truth.flicker = testing::FlickerSampling::kIntegrated;  // see ...IeeeFloorAtShortTau
  }
  return s;
}

double TruthOf(const testing::GyroTruth& t, int term) {
  const double v[kNoiseTermCount] = {t.q_rad, t.n_rad_sqrt_s, t.b_rad_s, t.k_rad_s_sqrt_s,
                                     t.r_rad_s2};
  return v[term];
}
double Value(const NoiseTerms& t, int term, bool se) {
  const double v[kNoiseTermCount] = {t.q_rad, t.n_rad_sqrt_s, t.b_rad_s, t.k_rad_s_sqrt_s,
                                     t.r_rad_s2};
  const double e[kNoiseTermCount] = {t.q_se, t.n_se, t.b_se, t.k_se, t.r_se};
  return se ? e[term] : v[term];
}

struct TermStats {
  std::vector<double> z;  // present terms, records where the term is positive
  int held_at_zero = 0;   // records where the term is fitted as 0
  int significant = 0;    // absent terms: false alarms; present terms: detections
  int unreliable = 0;     // records where the term is flagged unreliable (all false alarms here)
  int readoff_above_limit = 0;     // not significant, slope read-off > 2x the upper limit
  int truth_below_limit = 0;       // present terms: truth <= the reported upper limit
  int held_truth_below_limit = 0;  // ... among the records where the term is held at 0
  // present terms: truth <= the upper limit AssessNoiseTerms reports for the same terms (the
  // check `compare` applies to its own fit), on the same table
  int truth_below_assessed_limit = 0;
};
struct Calibration {
  TermStats term[kNoiseTermCount];
  int records = 0;
  int chi2_above_p01 = 0;  // records with p-value < 0.01
};

double StandardDeviation(const std::vector<double>& x) {
  double mean = 0.0, ss = 0.0;
  for (double v : x) mean += v / x.size();
  for (double v : x) ss += (v - mean) * (v - mean);
  return std::sqrt(ss / (x.size() - 1.0));
}
double Mean(const std::vector<double>& x) {
  double mean = 0.0;
  for (double v : x) mean += v / x.size();
  return mean;
}

Calibration Simulate(const Scenario& s, int records, unsigned seed_base, bool correlated) {
  Calibration c;
  NoiseFitOptions options;
  options.correlated = correlated;
  for (int r = 0; r < records; ++r) {
    const Eigen::VectorXd rate =
        testing::SimulateGyro(s.truth, s.samples, s.rate_hz, seed_base + r);
    const AllanResult allan = ComputeAllan(rate, s.rate_hz, AllanOptions());
    const NoiseFitResult fit = FitNoiseTerms(allan.table, options);
    const NoiseFitResult assessed = AssessNoiseTerms(allan.table, fit.terms, nullptr, 0.0, options);
    ++c.records;
    if (fit.p_value < 0.01) ++c.chi2_above_p01;
    for (int j = 0; j < kNoiseTermCount; ++j) {
      TermStats& t = c.term[j];
      const double truth = TruthOf(s.truth, j), est = Value(fit.terms, j, false);
      if (fit.assessment[j].significant) ++t.significant;
      const double readoff = Value(fit.slope_readoff, j, false);
      if (!fit.assessment[j].significant && readoff > 2.0 * fit.assessment[j].upper_limit)
        ++t.readoff_above_limit;
      if (!fit.assessment[j].reliable) {
        ++t.unreliable;
        if (t.unreliable <= 2)
          std::printf("  %s %s flagged: %s\n", s.name, TermSymbol(j),
                      fit.assessment[j].reason.c_str());
      }
      if (!(est > 0.0)) ++t.held_at_zero;
      if (truth > 0.0 && est > 0.0) t.z.push_back((est - truth) / Value(fit.terms, j, true));
      if (truth > 0.0 && truth <= assessed.assessment[j].upper_limit)
        ++t.truth_below_assessed_limit;
      if (truth > 0.0 && truth <= fit.assessment[j].upper_limit) {
        ++t.truth_below_limit;
        if (!(est > 0.0)) ++t.held_truth_below_limit;
      }
    }
  }
  return c;
}

void Print(const Scenario& s, const Calibration& c, const char* fit) {
  std::printf("%s, %s fit, %d records, p < 0.01 in %d\n", s.name, fit, c.records, c.chi2_above_p01);
  for (int j = 0; j < kNoiseTermCount; ++j) {
    const TermStats& t = c.term[j];
    if (TruthOf(s.truth, j) > 0.0)
      std::printf(
          "  %s present: sd(z) %.3f mean(z) %+.3f, held at 0 in %d, significant %d, "
          "unreliable %d, truth below the upper limit in %d (of the held: %d; below the checked "
          "terms' limit in %d)\n",
          TermSymbol(j), t.z.size() > 1 ? StandardDeviation(t.z) : NAN,
          t.z.empty() ? NAN : Mean(t.z), t.held_at_zero, t.significant, t.unreliable,
          t.truth_below_limit, t.held_truth_below_limit, t.truth_below_assessed_limit);
    else
      std::printf(
          "  %s absent: significant in %d (%.1f %%), held at 0 in %d, unreliable %d, read-off "
          "above 2x the upper limit %d\n",
          TermSymbol(j), t.significant, 100.0 * t.significant / c.records, t.held_at_zero,
          t.unreliable, t.readoff_above_limit);
  }
  std::fflush(stdout);
}

// Tolerances for n records: the sample sd of z has relative sd ~ sqrt((kurtosis - 1) / (4 n))
// (= 1 / sqrt(2 (n - 1)) for Gaussian z); the z of amplitudes from few-dof Allan points are
// heavier-tailed; allowing kurtosis 5 (Gaussian: 3), the relative sd is sqrt(4 / (4 * 80)) =
// 0.11 and 2 sd = 0.22 around the claimed [0.8, 1.25]: the CI test accepts [0.8 / 1.22,
// 1.25 * 1.22] = [0.65, 1.53] and fails on the uncalibrated diagonal fit where it is worst (study:
// white N 1.97, navigation K 2.13). False alarms: the claim is p <= 0.05; with 80 records the
// count is binomial, 8 or more (10 %) has probability 0.047 at p = 0.05, so 8 fails (a true rate
// of 0.15 passes with probability 0.07 only).
// A present term that the record does not determine is held at 0 in some records (the five-term
// scenario's R: 17 %), where z has no Gaussian meaning; those records are judged by the upper
// limit instead, sqrt(theta + 2 se(theta)), a one-sided 97.7 % bound for a calibrated theta, over
// every record (held or not): with 80 records the count of misses is binomial with mean 1.8 and
// sd 1.3, so 7 or more (coverage below 0.92) has probability 0.003 at 97.7 % and fails. The sd(z)
// tolerance above uses the records where the term is positive, of which at least 40 are required.
void ExpectCalibrated(const Scenario& s, const Calibration& c) {
  for (int j = 0; j < kNoiseTermCount; ++j) {
    const TermStats& t = c.term[j];
    if (TruthOf(s.truth, j) > 0.0) {
      EXPECT_GE(t.truth_below_limit, 0.92 * c.records) << s.name << " " << TermSymbol(j);
      // The same claim for the limit AssessNoiseTerms puts on the same terms (compare's check).
      EXPECT_GE(t.truth_below_assessed_limit, 0.92 * c.records)
          << s.name << " " << TermSymbol(j) << " (checked terms)";
      ASSERT_GE(t.z.size(), 40u) << s.name << " " << TermSymbol(j);
      const double k = 2.0 * std::sqrt(4.0 / (4.0 * t.z.size()));
      const double sd = StandardDeviation(t.z);
      EXPECT_GT(sd, 0.8 / (1.0 + k)) << s.name << " " << TermSymbol(j);
      EXPECT_LT(sd, 1.25 * (1.0 + k)) << s.name << " " << TermSymbol(j);
    } else {
      EXPECT_LT(t.significant, 0.1 * c.records) << s.name << " " << TermSymbol(j);
    }
    // The records follow the five-term model, so every "unreliable" flag is a false alarm; the
    // claim is <= 5 % per term, tested as the false alarms above.
    EXPECT_LT(t.unreliable, 0.1 * c.records) << s.name << " " << TermSymbol(j);
  }
}

// The calibration measures the fit only if its records follow the model the fit assumes. At
// m = 1..4 the flicker term is buried under N (navigation: 0.3 % of sigma^2 at m = 1), but the
// estimate there is so precise (relative sd 0.34 % at m = 1 on 2^18 samples) that Kasdin's excess
// over the IEEE floor (1.44x at m = 1, 1.15x at 2, 1.05x at 4) is 0.45 sd at m = 1, a rise at
// short tau that the fit reads as quantization: by the GLS normal equations it moves Q^2 by
// +0.17 of its standard error in the navigation scenario and doubles Q's false alarms there
// (docs/allan-noise-fit.md). Every
// scenario's flicker must have the floor at m = 1, 2, 4, 8: the mean over records of sigma^2(m) /
// floor within 4 standard errors of 1.
TEST(NoiseFitCalibration, SimulatedBiasInstabilityHasTheIeeeFloorAtShortTau) {
  for (const Scenario& s : Scenarios()) {
    if (!(s.truth.b_rad_s > 0.0)) continue;
    testing::GyroTruth b;
    b.b_rad_s = s.truth.b_rad_s;
    b.flicker = s.truth.flicker;
    const double floor = 2.0 * std::log(2.0) / 3.14159265358979323846 * b.b_rad_s * b.b_rad_s;
    constexpr int kRecords = 100;
    std::vector<std::vector<double>> ratio(4);
    for (int r = 0; r < kRecords; ++r) {
      const AllanResult allan = ComputeAllan(
          testing::SimulateGyro(b, 1 << 14, s.rate_hz, 23000 + r), s.rate_hz, AllanOptions());
      for (int i = 0; i < 4; ++i) {
        ASSERT_EQ(allan.table.m[i], 1LL << i);
        ratio[i].push_back(allan.table.sigma[i] * allan.table.sigma[i] / floor);
      }
    }
    for (int i = 0; i < 4; ++i) {
      const double se = StandardDeviation(ratio[i]) / std::sqrt(kRecords);
      EXPECT_NEAR(Mean(ratio[i]), 1.0, 4.0 * se) << s.name << " m = " << (1 << i);
    }
  }
}

TEST(NoiseFitCalibration, WhiteNoiseGivesCalibratedArwAndNoSpuriousTerms) {
  const Scenario s = Scenarios()[0];
  const Calibration c = Simulate(s, 80, 20000, true);
  Print(s, c, "GLS");
  ExpectCalibrated(s, c);
}

// All five terms together, R at the edge of what a 7.3 h record determines (held at 0 in about a
// sixth of the records): sd(z) where fitted, the upper limit's coverage over every record.
TEST(NoiseFitCalibration, FiveTermsTogetherGiveCalibratedTerms) {
  const Scenario s = Scenarios()[1];
  const Calibration c = Simulate(s, 80, 24000, true);
  Print(s, c, "GLS");
  ExpectCalibrated(s, c);
}

TEST(NoiseFitCalibration, NavigationGradeMixtureGivesCalibratedTerms) {
  const Scenario s = Scenarios()[2];
  const Calibration c = Simulate(s, 80, 21000, true);
  Print(s, c, "GLS");
  ExpectCalibrated(s, c);
}

// N's read-off here is taken where Q and B mix (noise_fit.h, read-off check), above 2x N's upper
// limit in most records; the model reproduces the curve there, so N must not be flagged more
// often than any term of a record that follows the model (ExpectCalibrated).
TEST(NoiseFitCalibration, AReadOffBetweenTwoFittedTermsDoesNotFlagTheAbsentTermBetweenThem) {
  const Scenario s = Scenarios()[3];
  const Calibration c = Simulate(s, 80, 22000, true);
  Print(s, c, "GLS");
  EXPECT_GT(c.term[1].readoff_above_limit, c.records / 2) << "the scenario no longer tests this";
  ExpectCalibrated(s, c);
}

TEST(NoiseFitCalibration, DISABLED_StudyOfAllScenariosWithAndWithoutCorrelation) {
  for (const Scenario& s : Scenarios())
    for (bool correlated : {true, false}) {
      const Calibration c = Simulate(s, 250, 40000, correlated);
      Print(s, c, correlated ? "GLS" : "diagonal");
    }
}

// Q's false alarms in the navigation scenario on seeds the design never saw (60000+), 1000
// records: for a calibrated, unbiased theta_Q the one-sided rate is 2.3 % and Q is held at 0 in
// half the records (docs/allan-noise-fit.md).
TEST(NoiseFitCalibration, DISABLED_StudyOfNavigationOnHeldOutSeeds) {
  const Scenario s = Scenarios()[2];
  Print(s, Simulate(s, 1000, 60000, true), "GLS");
}

// The five-term scenario's ramp (K/R crossover at 3000 s) is significant in only ~5 % of 7.3 h
// records; here R is twice as strong (K/R crossover at 750 s) so that the record
// determines it, GLS only.
TEST(NoiseFitCalibration, DISABLED_StudyOfFiveTermsWithAMeasurableRamp) {
  Scenario s = Scenarios()[1];
  s.name = "five terms, R x2";
  s.truth.r_rad_s2 *= 2.0;
  Print(s, Simulate(s, 250, 42000, true), "GLS");
}

}  // namespace
}  // namespace fogpipe::allan
