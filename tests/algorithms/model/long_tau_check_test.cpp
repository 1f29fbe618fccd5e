#include "algorithms/model/long_tau_check.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "algorithms/model/compare.h"
#include "algorithms/simulation/random.h"
#include "hidden_effects.h"

namespace fogpipe::model {
namespace {

namespace sim = fogpipe::simulation;
using testing::HiddenCase;
using testing::MakeHiddenCase;

StochasticModel OneTerm(Term term) {
  StochasticModel m;
  m.terms = {term};
  m.q_rad = 2e-6;
  m.n_rad_sqrt_s = 3e-6;
  m.b_rad_s = 5e-7;
  m.k_rad_s_sqrt_s = 4e-8;
  m.r_rad_s2 = 1e-10;
  m.gm_sigma_rad_s = 2e-6;
  m.gm_correlation_time_s = 120;
  return m;
}

TEST(LongTauCheck, TheBlockDifferenceVarianceIsTwiceEachTermsAllanLaw) {
  // gamma_0 / 2 from the generalised covariances against fogpipe::allan's closed forms (IEEE
  // Std 952 Annex C; Gauss-Markov: the first-order Markov Allan law), an independent derivation.
  for (Term term : {Term::kQuantization, Term::kWhite, Term::kBiasInstability,
                    Term::kRateRandomWalk, Term::kRateRamp, Term::kGaussMarkov}) {
    const StochasticModel m = OneTerm(term);
    for (double tau : {0.1, 3.0, 100.0, 5000.0}) {
      const double half = BlockDifferenceAutocovariance(m, tau, 1)[0] / 2;
      EXPECT_NEAR(half / TermAllanVariance(m, term, tau), 1.0, 1e-9)
          << ToString(term) << " tau " << tau;
    }
  }
}

TEST(LongTauCheck, NeighbouringIncrementsCorrelateAsWhiteRateAndRandomWalkDo) {
  // Non-overlapping Allan differences: -1/2 at lag 1 for white rate noise and 0 beyond; +1/4 at
  // lag 1 for a rate random walk (block means of Brownian motion) and 0 beyond.
  const std::vector<double> white = BlockDifferenceAutocovariance(OneTerm(Term::kWhite), 10, 4);
  EXPECT_NEAR(white[1] / white[0], -0.5, 1e-12);
  EXPECT_NEAR(white[2] / white[0], 0.0, 1e-12);
  const std::vector<double> walk =
      BlockDifferenceAutocovariance(OneTerm(Term::kRateRandomWalk), 10, 4);
  EXPECT_NEAR(walk[1] / walk[0], 0.25, 1e-9);
  EXPECT_NEAR(walk[2] / walk[0], 0.0, 1e-9);
  EXPECT_NEAR(walk[3] / walk[0], 0.0, 1e-9);
}

TEST(LongTauCheck, TheKurtosisDeviateMatchesScipysKurtosisTest) {
  // (m, b2, z) from scipy 1.10.1: b2 = scipy.stats.kurtosis(x, fisher=False) and z =
  // scipy.stats.kurtosistest(x).statistic for normal and Student t(3) samples
  // (numpy.random.default_rng(1)); an independent implementation of Anscombe & Glynn (1983).
  struct Reference {
    int m;
    double b2, z;
  };
  for (const Reference& r : {Reference{20, 2.479081627896168, -0.13172496071869524},
                             Reference{25, 5.188950199131832, 2.287904009552619},
                             Reference{51, 16.845036117962636, 5.083272592211937},
                             Reference{200, 2.767218664966632, -0.5456736531025973},
                             Reference{1000, 32.481962965313585, 17.38127717330121}})
    EXPECT_NEAR(KurtosisNormalDeviate(r.b2, r.m), r.z, 1e-9) << r.m;
}

TEST(LongTauCheck, TheBetaQuantileMatchesItsClosedFormsAtUnitParameters) {
  // Beta(1, b): 1 - (1 - p)^(1/b); Beta(a, 1): p^(1/a).
  for (double p : {1e-4, 0.025, 0.5, 0.975, 0.9999}) {
    EXPECT_NEAR(BetaQuantile(p, 1, 7), 1 - std::pow(1 - p, 1.0 / 7), 1e-10) << p;
    EXPECT_NEAR(BetaQuantile(p, 5, 1), std::pow(p, 1.0 / 5), 1e-10) << p;
  }
  // Symmetry: Beta(a, a) has median 1/2.
  EXPECT_NEAR(BetaQuantile(0.5, 6, 6), 0.5, 1e-10);
}

TEST(LongTauCheck, TheInnovationsAreTheCholeskySolveOfTheToeplitzCovariance) {
  // Durbin-Levinson against Eigen's LLT of the full Toeplitz matrix, under a model with every
  // long-tau term.
  StochasticModel m;
  m.terms = {Term::kWhite, Term::kBiasInstability, Term::kRateRandomWalk, Term::kRateRamp};
  m.n_rad_sqrt_s = 3e-6;
  m.b_rad_s = 5e-7;
  m.k_rad_s_sqrt_s = 4e-8;
  m.r_rad_s2 = 1e-11;
  const int size = 40;
  const std::vector<double> gamma = BlockDifferenceAutocovariance(m, 300.0, size);
  Eigen::MatrixXd toeplitz(size, size);
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j) toeplitz(i, j) = gamma[std::abs(i - j)];
  simulation::RandomSource rng(9);
  const Eigen::VectorXd d = rng.Normals(size) * std::sqrt(gamma[0]);
  std::vector<double> e;
  ASSERT_TRUE(WhitenedInnovations(std::vector<double>(d.data(), d.data() + size), gamma, &e));
  const Eigen::VectorXd expected = toeplitz.llt().matrixL().solve(d);
  for (int i = 0; i < size; ++i) EXPECT_NEAR(e[i], expected[i], 1e-8) << i;
}

TEST(LongTauCheck, UnderTheTrueModelTheFlagRateIsAtMostItsLevel) {
  // White rate noise plus a rate random walk that rules the long taus, checked against the true
  // model (no fit): the statistics' own laws. 300 seeds at the nominal level 0.02 (Bonferroni,
  // so at most 0.02): at most 0.02 x 300 + 3 sd = 6 + 7.3 flagged.
  const double fs = 1.0, s = 0.01, walk = 5e-4;  // per-sample sds
  const long n = 1L << 14;
  StochasticModel m;
  m.terms = {Term::kWhite, Term::kRateRandomWalk};
  m.n_rad_sqrt_s = s / std::sqrt(fs);
  m.k_rad_s_sqrt_s = walk * std::sqrt(fs);
  int flagged = 0, evaluated = 0;
  for (int seed = 1; seed <= 300; ++seed) {
    simulation::RandomSource rng(seed);
    const Eigen::VectorXd white = s * rng.Normals(n), steps = walk * rng.Normals(n);
    Eigen::VectorXd x(n);
    double level = 0;
    for (long i = 0; i < n; ++i) {
      level += steps[i];
      x[i] = white[i] + level;
    }
    const LongTauCheck check = CheckLongTauTerms(x, fs, m, {});
    evaluated += check.evaluated;
    flagged += check.flagged;
  }
  EXPECT_EQ(evaluated, 300);
  EXPECT_LE(flagged, 13);
  std::printf("flagged under the true model: %d of 300\n", flagged);
}

TEST(LongTauCheck, IsNotEvaluatedWhereWhiteNoiseDominatesEveryTau) {
  const StochasticModel m = OneTerm(Term::kWhite);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(10000);
  const LongTauCheck check = CheckLongTauTerms(x, 10.0, m, {});
  EXPECT_FALSE(check.evaluated);
  EXPECT_FALSE(check.flagged);
}

// The recordings of the study below: "none", "steps" (3-5 bias steps), "telegraph" (two levels,
// mean dwell 1800 s), "quadratic" (a quadratic temperature dependence), "hysteresis" (a thermal
// hysteresis), "step_gm" (a bias step beside Gauss-Markov noise), each at peak Allan signature k
// (hidden_effects.h).
HiddenCase StudyCase(const std::string& kind, int seed, double k, double dwell_s = 1800.0) {
  if (kind == "step_gm") {
    HiddenCase c = MakeHiddenCase(seed, {sim::Term::kGaussMarkov, sim::Term::kBiasStep});
    return c;
  }
  if (kind == "rrw" || kind == "rrw_telegraph") {
    // A rate random walk 30x the navigation-grade one, so that it dominates the long taus.
    sim::GyroSimulatorOptions options = testing::HiddenEffectOptions(seed, {});
    options.errors.k_rad_s_sqrt_s *= 30;
    HiddenCase c = MakeHiddenCase(options);
    if (kind == "rrw_telegraph") testing::AddTelegraph(k, dwell_s, seed, &c);
    return c;
  }
  HiddenCase c = MakeHiddenCase(seed, {});
  if (kind == "hysteresis") testing::AddThermalHysteresis(k, &c);
  if (kind == "steps") testing::AddBiasSteps(k, seed, &c);
  if (kind == "telegraph") testing::AddTelegraph(k, dwell_s, seed, &c);
  if (kind == "quadratic") testing::AddQuadraticTemperatureBias(k, seed, &c);
  return c;
}

// The default model's base evaluation (what `compare` reports) of StudyCase(kind): whether the
// long-tau check flags it, and whether the views call it consistent.
struct Outcome {
  bool flagged = false, consistent = false;
};
Outcome Evaluate(const std::string& kind, int seed, double k, double dwell_s = 1800.0) {
  HiddenCase c = StudyCase(kind, seed, k, dwell_s);
  c.input.rate_rad_s = &c.recording.rate_rad_s;  // the copy's own rate
  const Evaluation e = EvaluateModel(c.input, DefaultTerms(), {});
  return {e.long_tau.flagged, e.views.consistent};
}
bool Flagged(const std::string& kind, int seed, double k, double dwell_s = 1800.0) {
  return Evaluate(kind, seed, k, dwell_s).flagged;
}

TEST(LongTauCheck, RaisesFewFalseAlarmsWhereATrueRandomWalkDominatesTheLongTaus) {
  // Effect-free navigation-grade records with K 30x the navigation one, so that the check is
  // evaluated (with the usual K it is not: B, K and R carry less than half the Allan variance at
  // every tau with 16 blocks of 6 h). Design seeds 1-60: 3 of 60 flagged at the default nominal
  // alpha 0.02 (6 of 60 at 0.05: the parameters are fitted on the same record). At a rate of
  // 5 %, at most 3 of 20 test seeds (P(X >= 4) = 1.6 % for Binomial(20, 0.05)).
  int flagged = 0;
  for (int seed = 101; seed <= 120; ++seed) flagged += Flagged("rrw", seed, 0);
  EXPECT_LE(flagged, 3);
}

TEST(LongTauCheck, FlagsBiasLevelsThatTheRandomWalkAbsorbs) {
  // Random telegraph switching between two levels with a mean dwell of 5400 s (about 4 switches
  // in 6 h), peak Allan signature 4x the noise: the fitted K comes out 0-40x its true value
  // and the verdict is "consistent" on 8 of 20 design seeds. Design seeds 1-20: flagged on 10.
  // At a detection rate of 0.5, at least 6 of 20 test seeds (P(X <= 5) = 2.1 % for
  // Binomial(20, 0.5)).
  int flagged = 0;
  for (int seed = 101; seed <= 120; ++seed) flagged += Flagged("telegraph", seed, 4.0, 5400.0);
  EXPECT_GE(flagged, 6);
}

TEST(LongTauCheck, FlagsAQuadraticTemperatureDependenceThatTheRandomWalkAbsorbs) {
  // Quadratic temperature dependence (hidden_effects.h) at signature 4x: K fitted 9-92x its
  // true value. Design seeds 1-20: flagged on 19. At a detection rate of 0.9, at least 15 of 20
  // test seeds (P(X <= 14) = 1.1 % for Binomial(20, 0.9)).
  int flagged = 0;
  for (int seed = 101; seed <= 120; ++seed) flagged += Flagged("quadratic", seed, 4.0);
  EXPECT_GE(flagged, 15);
}

TEST(LongTauCheck, FlagsAThermalHysteresisThatTheViewsMiss) {
  // A bias +-a following the sign of dT/dt (heating against cooling) at signature 4x: a square
  // wave at the thermal period, absorbed by the fitted B and K, so that the views pass (verdict
  // "consistent" on 18 of 20 design seeds). Design seeds 1-20: flagged while the views pass on
  // 12. At a rate of 0.6, at least 7 of 20 test seeds (P(X <= 6) = 0.6 % for Binomial(20, 0.6)).
  int flagged_while_consistent = 0;
  for (int seed = 101; seed <= 120; ++seed) {
    const Outcome o = Evaluate("hysteresis", seed, 4.0);
    flagged_while_consistent += o.flagged && o.consistent;
  }
  EXPECT_GE(flagged_while_consistent, 7);
}

// The rates behind the assertions (not run by ctest):
//   FOGPIPE_LONG_TAU_SEEDS=1-20 FOGPIPE_LONG_TAU_KIND=telegraph FOGPIPE_LONG_TAU_K=4
//   model_long_tau_check_test --gtest_also_run_disabled_tests --gtest_filter='*Study*'
TEST(LongTauStudy, DISABLED_FlagsOverSeeds) {
  const char* seeds = std::getenv("FOGPIPE_LONG_TAU_SEEDS");
  const char* kind = std::getenv("FOGPIPE_LONG_TAU_KIND");
  const char* k_env = std::getenv("FOGPIPE_LONG_TAU_K");
  ASSERT_TRUE(seeds && kind);
  int seed0 = 0, seed1 = 0;
  ASSERT_EQ(std::sscanf(seeds, "%d-%d", &seed0, &seed1), 2);
  const double k = k_env ? std::atof(k_env) : 4.0;
  for (int seed = seed0; seed <= seed1; ++seed) {
    const char* dwell = std::getenv("FOGPIPE_LONG_TAU_DWELL");
    HiddenCase c = StudyCase(kind, seed, k, dwell ? std::atof(dwell) : 1800.0);
    c.input.rate_rad_s = &c.recording.rate_rad_s;  // the copy's own rate
    CompareOptions options;
    if (const char* alpha = std::getenv("FOGPIPE_LONG_TAU_ALPHA"))
      options.long_tau.alpha = std::atof(alpha);
    const CompareResult r = Compare(c.input, DefaultTerms(), options);
    const double k_true = c.recording.truth.options.errors.k_rad_s_sqrt_s;
    const double k_fit = r.base.stochastic.model.k_rad_s_sqrt_s;
    std::printf("LONGTAU %s k %.1f seed %d K %.3g/%.3g = %.2f flagged %d | %s | %s | %s\n", kind, k,
                seed, k_fit, k_true, k_true > 0 ? k_fit / k_true : 0.0, r.base.long_tau.flagged,
                r.verdict.status.c_str(), r.base.long_tau.message.c_str(),
                r.summary.message.c_str());
    std::printf("    verdict: %s\n", r.verdict.text.c_str());
    for (const LongTauPoint& p : r.base.long_tau.points)
      std::printf(
          "    tau %.4g m %d %s share %.2f kurt %.2f/%.2f at %.0f LB %.2f/%.2f (%d) low %.3f "
          "[%.3f, %.3f] (%d)\n",
          p.tau_s, p.blocks, p.dominant_term.c_str(), p.share, p.kurtosis_z, p.kurtosis_critical,
          p.jump_time_s, p.portmanteau, p.portmanteau_critical, p.lags, p.low_frequency,
          p.low_frequency_low, p.low_frequency_high, p.low_bins);
    std::fflush(stdout);
  }
}

}  // namespace
}  // namespace fogpipe::model
