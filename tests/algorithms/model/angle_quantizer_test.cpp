#include "algorithms/model/angle_quantizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>

#include "algorithms/common/units.h"
#include "algorithms/model/compare.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "hidden_effects.h"
#include "independent_records.h"

namespace fogpipe::model {
namespace {

namespace sim = fogpipe::simulation;

// An undithered counter of step q over white rate noise of per-sample angle sd sigma and a bias
// (1 h at 10 Hz), with its true rate.
struct Counter {
  Eigen::VectorXd true_rate, rate;
  double q = 0, sigma = 0, fs = 10.0;
};
Counter MakeCounter(std::uint64_t seed, double sigma_over_q) {
  std::mt19937_64 g(seed * 0x9E3779B97F4A7C15ULL + 0xA11CEULL);
  std::normal_distribution<double> normal(0.0, 1.0);
  Counter c;
  c.q = units::ArcsecToQuantization(0.5);
  c.sigma = sigma_over_q * c.q;
  const Eigen::Index n = 36000;
  const double bias_per_sample = 0.037 * c.q;
  c.true_rate.resize(n);
  c.rate.resize(n);
  double angle = 0, previous = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    c.true_rate[k] = (bias_per_sample + c.sigma * normal(g)) * c.fs;
    angle += c.true_rate[k] / c.fs;
    const double counted = c.q * std::round(angle / c.q);
    c.rate[k] = (counted - previous) * c.fs;
    previous = counted;
  }
  return c;
}

// The drawn angle stays in the counter's boxes: x_hat_k - theta_k = u_{k+1} - u_0 with every u in
// [-q/2, q/2], so its range over the record is at most one step.
TEST(ImputeAngleOnLattice, KeepsTheAngleWithinTheCountersSteps) {
  const Counter c = MakeCounter(1, 0.15);
  const AngleLattice lattice = DetectAngleLattice(c.rate, c.fs);
  ASSERT_TRUE(lattice.on_lattice);
  AngleQuantizerFit fit;
  const Eigen::VectorXd imputed =
      ImputeAngleOnLattice(c.rate, c.fs, lattice, c.sigma, AngleQuantizerOptions(), &fit);
  ASSERT_TRUE(fit.ok) << fit.message;
  double difference = 0, low = 0, high = 0;
  for (Eigen::Index k = 0; k < imputed.size(); ++k) {
    difference += (imputed[k] - c.rate[k]) / c.fs;
    low = std::min(low, difference);
    high = std::max(high, difference);
  }
  EXPECT_LE(high - low, c.q * (1.0 + 1e-9));
  EXPECT_GT(high - low, 0.5 * c.q);  // it does move within the steps
}

// Under the model the draw gives the rate the counter hid: white, of per-sample variance
// sigma^2 fs^2 (the raw counter's increments are correlated, their lag-1 correlation about -0.3).
// Sampling: var ratio sd sqrt(2 / n) = 0.0075, r_1 sd 1 / sqrt(n) = 0.0053 (n = 36000); the grid
// adds a white angle error of variance (q / cells)^2 / 12, at most 0.7 % of the variance at
// sigma / q = 0.1 with 48 cells. Bounds: 4.5 sd plus that bias.
TEST(ImputeAngleOnLattice, RestoresAWhiteRateOfTheModelsVariance) {
  for (double sigma_over_q : {0.1, 0.2, 0.3}) {
    SCOPED_TRACE(sigma_over_q);
    const Counter c = MakeCounter(2, sigma_over_q);
    const AngleLattice lattice = DetectAngleLattice(c.rate, c.fs);
    ASSERT_TRUE(lattice.on_lattice) << lattice.message;
    AngleQuantizerFit fit;
    const Eigen::VectorXd imputed =
        ImputeAngleOnLattice(c.rate, c.fs, lattice, c.sigma, AngleQuantizerOptions(), &fit);
    ASSERT_TRUE(fit.ok);
    const Eigen::VectorXd centred = imputed.array() - imputed.mean();
    const double n = static_cast<double>(centred.size());
    const double variance = centred.squaredNorm() / n;
    const double expected = c.sigma * c.sigma * c.fs * c.fs;
    EXPECT_NEAR(variance / expected, 1.0, 4.5 * 0.0075 + 0.007);
    const double r1 =
        centred.head(centred.size() - 1).dot(centred.tail(centred.size() - 1)) / (n * variance);
    EXPECT_LT(std::abs(r1), 4.5 * 0.0053 + 0.004);
  }
}

TEST(ImputeAngleOnLattice, RefusesARateThatIsNotACounter) {
  const Counter c = MakeCounter(3, 0.2);
  AngleQuantizerFit fit;
  const Eigen::VectorXd out =
      ImputeAngleOnLattice(c.true_rate, c.fs, DetectAngleLattice(c.true_rate, c.fs), c.sigma,
                           AngleQuantizerOptions(), &fit);
  EXPECT_FALSE(fit.ok);
  EXPECT_NE(fit.message.find("not an angle counter"), std::string::npos) << fit.message;
  EXPECT_EQ(out, c.true_rate);
}

// The EM map as a contraction at rate lambda towards sigma_star in log sigma:
// log F(sigma) = log sigma_star + lambda (log sigma - log sigma_star).
double LinearEmMap(double sigma, double sigma_star, double lambda) {
  return sigma_star * std::pow(sigma / sigma_star, lambda);
}

// The first round is the EM's own step and its own settling (no extrapolation without a second
// point): as before the acceleration.
TEST(NextEmNoise, TheFirstRoundIsThePlainEmStep) {
  const AngleQuantizerOptions options;
  bool settled = true;
  EXPECT_EQ(NextEmNoise(1.0, 0.9, 0, 0, options, &settled), 0.9);
  EXPECT_FALSE(settled);
  EXPECT_EQ(NextEmNoise(1.0, 0.99, 0, 0, options, &settled), 0.99);
  EXPECT_TRUE(settled);
}

// On a map linear in log sigma the secant through two draws is exact: after one plain step the
// extrapolated step lands on the fixed point (to rounding), where plain iteration at lambda 0.8
// would still be 0.8^2 of the way out (start 2.5 times the fixed point: 1.34 times).
TEST(NextEmNoise, OnALinearContractionTheSecondStepLandsOnTheFixedPoint) {
  const AngleQuantizerOptions options;
  const double star = 2.0e-7, lambda = 0.8;
  const double sigma0 = 2.5 * star, refitted0 = LinearEmMap(sigma0, star, lambda);
  bool settled = true;
  const double sigma1 = NextEmNoise(sigma0, refitted0, 0, 0, options, &settled);
  EXPECT_FALSE(settled);
  const double refitted1 = LinearEmMap(sigma1, star, lambda);
  const double sigma2 = NextEmNoise(sigma1, refitted1, sigma0, refitted0, options, &settled);
  EXPECT_FALSE(settled);  // the EM moved by 17 %
  EXPECT_NEAR(sigma2 / star, 1.0, 1e-12);
  bool settled_at_fixed_point = false;
  NextEmNoise(sigma2, LinearEmMap(sigma2, star, lambda), sigma1, refitted1, options,
              &settled_at_fixed_point);
  EXPECT_TRUE(settled_at_fixed_point);
}

// Safeguards: a rate above 1 - 1 / max_acceleration extrapolates max_acceleration EM steps, no
// more; a secant no contraction has (expanding, or overshooting to the far side) gives the EM's
// step.
TEST(NextEmNoise, TheExtrapolationIsBoundedAndFallsBackToThePlainStep) {
  AngleQuantizerOptions options;
  options.max_acceleration = 10.0;
  const double star = 1.0;
  bool settled = false;
  {  // lambda 0.97: Aitken would take 0.97 / 0.03 = 32 steps; capped at 10
    const double s0 = 3.0, r0 = LinearEmMap(s0, star, 0.97), s1 = r0;
    const double r1 = LinearEmMap(s1, star, 0.97);
    const double next = NextEmNoise(s1, r1, s0, r0, options, &settled);
    EXPECT_NEAR(std::log(next / s1), 10.0 * std::log(r1 / s1), 1e-12);
  }
  {  // expanding (lambda 1.2): the plain step
    const double s0 = 3.0, r0 = LinearEmMap(s0, star, 1.2), s1 = 2.0;
    const double r1 = LinearEmMap(s1, star, 1.2);
    EXPECT_EQ(NextEmNoise(s1, r1, s0, r0, options, &settled), r1);
  }
  {  // oscillating (lambda -0.5, secant slope -1.5): the plain step
    const double s0 = 3.0, r0 = LinearEmMap(s0, star, -0.5), s1 = r0;
    const double r1 = LinearEmMap(s1, star, -0.5);
    EXPECT_EQ(NextEmNoise(s1, r1, s0, r0, options, &settled), r1);
  }
  options.max_acceleration = 1.0;  // the plain EM
  const double s0 = 3.0, r0 = LinearEmMap(s0, star, 0.8), s1 = r0;
  const double r1 = LinearEmMap(s1, star, 0.8);
  EXPECT_NEAR(NextEmNoise(s1, r1, s0, r0, options, &settled), r1, 1e-15);
  options.max_acceleration = 0.5;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_acceleration"), std::string::npos);
}

// With angle_quantizer in the model, Compare's lattice (the verdict's and the report's) is the one
// the term drew on; without it, the angle_quantizer trial draws on Compare's. Non-default lattice
// options (11 lags) tell a lattice tested with other options apart.
TEST(AngleQuantizer, CompareReportsTheLatticeTheTermDrewOn) {
  const Counter c = MakeCounter(4, 0.15);
  CompareInput input;
  input.rate_rad_s = &c.rate;
  input.sample_rate_hz = c.fs;
  CompareOptions options;
  options.angle_lattice.whiteness_lags = 12;
  const AngleLattice expected = DetectAngleLattice(c.rate, c.fs, options.angle_lattice);
  ASSERT_TRUE(expected.coarse) << expected.message;
  ASSERT_EQ(expected.whiteness_dof, 11);
  const auto expect_same = [](const AngleLattice& a, const AngleLattice& b) {
    EXPECT_EQ(a.on_lattice, b.on_lattice);
    EXPECT_EQ(a.coarse, b.coarse);
    EXPECT_EQ(a.step_rad, b.step_rad);
    EXPECT_EQ(a.offset_rad, b.offset_rad);
    EXPECT_EQ(a.whiteness_statistic, b.whiteness_statistic);
    EXPECT_EQ(a.whiteness_dof, b.whiteness_dof);
    EXPECT_EQ(a.message, b.message);
  };
  std::vector<ModelTerm> terms = DefaultTerms();
  terms.push_back(Term::kAngleQuantizer);
  const CompareResult with = Compare(input, terms, options);
  ASSERT_TRUE(HasResult(with.summary.termination)) << with.summary.message;
  ASSERT_TRUE(with.base.angle_quantizer.ok);
  expect_same(with.angle_lattice, with.base.angle_quantizer.lattice);
  expect_same(with.angle_lattice, expected);
  const CompareResult without = Compare(input, DefaultTerms(), options);
  ASSERT_TRUE(HasResult(without.summary.termination));
  expect_same(without.angle_lattice, expected);
  for (const Evaluation& trial : without.trials)
    if (trial.angle_quantizer.ok) expect_same(trial.angle_quantizer.lattice, expected);
}

// ---- The term's proof in compare (slow) ----

enum class Source { kUndithered, kDithered, kSimulated, kSimulatedQ2 };

struct QuantizerScore {
  bool inconsistent = false, suggested = false, first_right = false, points = false;
  bool other_suggested = false;  // a suggestion other than angle_quantizer
  std::string first = "none";
  double error_before = 0, error_after = 0;
  bool consistent_after = false;
  double step_error = std::numeric_limits<double>::infinity();  // |q - truth| / max(1e-6 q, 3 SE)
  double n_error = std::numeric_limits<double>::infinity();     // |N - truth| / max(10 %, 3 SE)
  double n_ratio = 0;                                           // N / truth after
  double sigma_over_q = 0;
  std::string failures, failures_after;
};

const Parameter* Param(const std::vector<Parameter>& ps, const std::string& name) {
  for (const Parameter& p : ps)
    if (p.name == name) return &p;
  return nullptr;
}

QuantizerScore ScoreQuantizer(Source source, int seed) {
  QuantizerScore s;
  testing::IndependentRecord record;
  sim::SimulatedRecording simulated;
  CompareInput input;
  double q = 0, n_true = 0;
  if (source == Source::kUndithered || source == Source::kDithered) {
    testing::IndependentRecordOptions ro;
    ro.quantizer = source == Source::kDithered ? testing::Quantizer::kDithered
                                               : testing::Quantizer::kUndithered;
    record = testing::MakeIndependentRecord(static_cast<std::uint64_t>(seed), ro);
    input = record.Input();
    q = record.q_rad * std::sqrt(12.0);
    n_true = record.n_rad_sqrt_s;
  } else {
    sim::GyroSimulatorOptions o =
        testing::HiddenEffectOptions(static_cast<std::uint64_t>(seed), {});
    o.errors.quantization_model = sim::QuantizationModel::kAngleQuantizer;
    if (source == Source::kSimulatedQ2) o.errors.q_rad = units::ArcsecToQuantization(2.0);
    simulated = sim::SimulateGyro(o);
    input.rate_rad_s = &simulated.rate_rad_s;
    input.sample_rate_hz = o.sample_rate_hz;
    q = o.errors.q_rad * std::sqrt(12.0);
    n_true = o.errors.n_rad_sqrt_s;
  }
  s.sigma_over_q = n_true / std::sqrt(input.sample_rate_hz) / q;
  const CompareOptions options;
  const CompareResult before = Compare(input, DefaultTerms(), options);
  if (!HasResult(before.summary.termination)) return s;
  s.error_before = before.base.views.error;
  s.inconsistent = !before.base.views.consistent;
  for (const Failure& f : before.base.views.failures)
    s.failures += (s.failures.empty() ? "" : ", ") + FormatFailure(f);
  s.suggested = before.verdict.suggestion.has_value();
  if (s.suggested) s.first = ToString(*before.verdict.suggestion);
  s.first_right = s.suggested && *before.verdict.suggestion == Term::kAngleQuantizer;
  s.other_suggested = s.suggested && !s.first_right;
  s.points = before.verdict.coarse_angle_quantization;
  std::vector<ModelTerm> terms = DefaultTerms();
  terms.push_back(Term::kAngleQuantizer);
  const Evaluation after = EvaluateModel(input, terms, options);
  if (!HasResult(after.termination)) return s;
  s.error_after = after.views.error;
  s.consistent_after = after.views.consistent;
  for (const Failure& f : after.views.failures)
    s.failures_after += (s.failures_after.empty() ? "" : ", ") + FormatFailure(f);
  const std::vector<Parameter> ps = ParametersOf(after, Term::kAngleQuantizer);
  if (const Parameter* step = Param(ps, "step"))
    s.step_error = std::abs(step->value - units::QuantizationToArcsec(q)) /
                   std::max(1e-6 * units::QuantizationToArcsec(q), 3.0 * step->standard_error);
  const double n_fit = after.stochastic.model.n_rad_sqrt_s;
  s.n_ratio = n_fit / n_true;
  s.n_error = std::abs(n_fit - n_true) / std::max(0.1 * n_true, 3.0 * after.stochastic.model.n_se);
  return s;
}

// The smallest k with P(X < k) <= alpha for X ~ Binomial(m, p): at the rate p, a count below k
// has probability at most alpha.
int BinomialLowerBound(int m, double p, double alpha) {
  double below = 0;
  for (int k = 0; k <= m; ++k) {
    const double pk =
        std::exp(std::lgamma(m + 1.0) - std::lgamma(k + 1.0) - std::lgamma(m - k + 1.0) +
                 k * std::log(p) + (m - k) * std::log1p(-p));
    if (below + pk > alpha) return k;
    below += pk;
  }
  return m;
}

TEST(BinomialLowerBound, IsTheOnePercentPointOfTheCount) {
  // Binomial(20, 0.82): P(X <= 11) = 0.0049, P(X <= 12) = 0.0177.
  EXPECT_EQ(BinomialLowerBound(20, 0.82, 0.01), 12);
  EXPECT_EQ(BinomialLowerBound(5, 0.5, 0.01), 0);
}

// The proof's criteria over seeds seed0..seed1 of `source`, on the records the default model
// finds inconsistent, each at least the count that `rate` reaches with probability >= 99 %
// (BinomialLowerBound); inconsistent before at least the 1 % point at `inconsistent_rate`;
// another term suggested on at most 10 % of the records, the term's requirement.
void ExpectProof(Source source, int seed0, int seed1, double rate, double inconsistent_rate) {
  int inconsistent = 0, first = 0, points = 0, step = 0, noise = 0, consistent_after = 0;
  int other = 0;
  std::string report;
  for (int seed = seed0; seed <= seed1; ++seed) {
    const QuantizerScore s = ScoreQuantizer(source, seed);
    other += s.other_suggested;
    if (!s.inconsistent) continue;
    ++inconsistent;
    first += s.first_right;
    points += s.points;
    step += s.step_error <= 1.0;
    noise += s.n_error <= 1.0;
    consistent_after += s.consistent_after;
    report += "seed " + std::to_string(seed) + ": first " + s.first + ", step " +
              std::to_string(s.step_error) + ", N " + std::to_string(s.n_error) + ", error " +
              std::to_string(s.error_before) + " -> " + std::to_string(s.error_after) + " " +
              s.failures_after + "\n";
  }
  const int records = seed1 - seed0 + 1;
  std::printf(
      "seeds %d-%d: inconsistent %d; of them first %d, points %d, step %d, N %d, consistent "
      "after %d; another term suggested %d\n",
      seed0, seed1, inconsistent, first, points, step, noise, consistent_after, other);
  EXPECT_GE(inconsistent, BinomialLowerBound(records, inconsistent_rate, 0.01));
  const int bound = BinomialLowerBound(inconsistent, rate, 0.01);
  EXPECT_GE(first, bound) << report;
  EXPECT_GE(points, bound) << report;
  EXPECT_GE(step, bound) << report;
  EXPECT_GE(noise, bound) << report;
  EXPECT_GE(consistent_after, bound) << report;
  EXPECT_LE(10 * other, records) << report;
}

// The proof on effect-free undithered counters with three aux channels (independent_records.h).
// Design seeds 3000-3039 (AngleQuantizerStudy; docs/compare.md): the default model inconsistent
// on 17, and on each of the 17 the first suggestion is angle_quantizer, the verdict names the
// counter, the step is right to rounding, N within max(10 %, 3 SE) and the model consistent with
// the term; no other term suggested on any of the 40. CI seeds 3100-3139 (ExpectProof): the
// rate 1 - 3 / 17 = 0.82 (the rule of three on 17 of 17); inconsistent before at the rate 0.27
// (below Clopper-Pearson's one-sided 95 % lower bound on 17 of 40, 0.29).
TEST(AngleQuantizer, OnUnditheredCountersTheTermIsSuggestedEstimatedAndMakesTheModelConsistent) {
  ExpectProof(Source::kUndithered, 3100, 3139, 0.82, 0.27);
}

// The second source: fogpipe's own quantizer at the navigation-grade draws of Q (`simulate
// --profile nav --angle-quantizer`, q 0.18-0.64 arcsec, sigma / q 0.13-0.81). Design seeds
// 3000-3019: inconsistent on 8, and on each of the 8 every criterion (N 0.988-1.012 of the
// truth); consistent with the term on 19 of 20; no other term suggested. CI seeds 3100-3119: the
// rate 1 - 3 / 8 = 0.625 (the rule of three on 8 of 8); inconsistent before at the rate 0.15
// (below Clopper-Pearson's one-sided 95 % lower bound on 8 of 20, 0.22).
TEST(AngleQuantizer,
     OnFogpipesSimulatedCountersTheTermIsSuggestedEstimatedAndMakesTheModelConsistent) {
  ExpectProof(Source::kSimulated, 3100, 3119, 0.625, 0.15);
}

// Controls: effect-free dithered counters with three aux channels. The dither makes the error
// white, so the counter is not coarse and angle_quantizer is never trialled. Design seeds
// 3000-3039: something suggested on 0 of 40 (inconsistent on 2). CI seeds 3100-3139: something
// suggested on at most 4 of 40 (the requirement's 10 %), angle_quantizer on none.
TEST(AngleQuantizer, DitheredCountersAreRarelyGivenASuggestionAndNeverTheTerm) {
  int suggested = 0, quantizer = 0;
  std::string report;
  for (int seed = 3100; seed <= 3139; ++seed) {
    const QuantizerScore s = ScoreQuantizer(Source::kDithered, seed);
    suggested += s.suggested;
    quantizer += s.first_right;
    if (s.suggested) report += "seed " + std::to_string(seed) + ": " + s.first + "\n";
  }
  std::printf("dithered 3100-3139: suggested %d, angle_quantizer %d\n", suggested, quantizer);
  EXPECT_LE(suggested, 4) << report;
  EXPECT_EQ(quantizer, 0) << report;
}

// fogpipe's own quantizer, `simulate --profile nav --angle-quantizer --q-arcsec 2` (q 6.93
// arcsec, sigma / q 0.01-0.02): design seeds 3000-3019: inconsistent, the term first, the verdict
// naming the counter and the step to rounding on 20 of 20; with the accelerated EM the error falls
// with the term from 112-984 to 0.59-0.94, consistent with it on 20 of 20, and N reads
// 0.962-1.243 of the truth, within max(10 %, 3 SE) on 14 of 20 (docs/compare.md; the plain EM gave
// 0.58-1.87, 13 of 20 and 1.12-1.71x). CI seeds 3100-3104: the first four criteria on every one
// (the counter's evidence is overwhelming: the portmanteau is 9-17x its critical value) and the
// error falling at least 10x on every one. Consistency after and N are not asserted: their design
// rates were set by the plain EM, and the rerun has not been held to CI seeds yet.
TEST(AngleQuantizer, FogpipesCoarseQuantizerGetsTheTermWhichTakesMostOfTheError) {
  int inconsistent = 0, first = 0, points = 0, step = 0, falls = 0, consistent_after = 0;
  std::string report;
  for (int seed = 3100; seed <= 3104; ++seed) {
    const QuantizerScore s = ScoreQuantizer(Source::kSimulatedQ2, seed);
    inconsistent += s.inconsistent;
    first += s.first_right;
    points += s.points;
    step += s.step_error <= 1.0;
    falls += 10.0 * s.error_after <= s.error_before;
    consistent_after += s.consistent_after;
    report += "seed " + std::to_string(seed) + ": first " + s.first + ", N/true " +
              std::to_string(s.n_ratio) + ", error " + std::to_string(s.error_before) + " -> " +
              std::to_string(s.error_after) + " " + s.failures_after + "\n";
  }
  std::printf(
      "q2 3100-3104: inconsistent %d, first %d, points %d, step %d, error falls 10x %d, "
      "consistent after %d\n%s",
      inconsistent, first, points, step, falls, consistent_after, report.c_str());
  EXPECT_EQ(inconsistent, 5);
  EXPECT_EQ(first, 5) << report;
  EXPECT_EQ(points, 5) << report;
  EXPECT_EQ(step, 5) << report;
  EXPECT_EQ(falls, 5) << report;
}

// The seed study behind the proof (not run by ctest):
//   FOGPIPE_QUANTIZER_SOURCE=undithered FOGPIPE_STUDY_SEEDS=3000-3039
//   model_angle_quantizer_test --gtest_also_run_disabled_tests --gtest_filter='*Study*'
// FOGPIPE_QUANTIZER_SOURCE: undithered, dithered (independent_records.h, three aux channels),
// simulated (fogpipe's quantizer, navigation-grade Q), simulated_q2 (Q 2 arcsec).
TEST(AngleQuantizerStudy, DISABLED_ProofOverSeeds) {
  const char* source_env = std::getenv("FOGPIPE_QUANTIZER_SOURCE");
  const char* seeds = std::getenv("FOGPIPE_STUDY_SEEDS");
  const std::string name = source_env ? source_env : "undithered";
  const Source source = name == "dithered"       ? Source::kDithered
                        : name == "simulated"    ? Source::kSimulated
                        : name == "simulated_q2" ? Source::kSimulatedQ2
                                                 : Source::kUndithered;
  int seed0 = 3000, seed1 = 3039;
  if (seeds) std::sscanf(seeds, "%d-%d", &seed0, &seed1);
  for (int seed = seed0; seed <= seed1; ++seed) {
    const QuantizerScore s = ScoreQuantizer(source, seed);
    std::printf(
        "QUANT %s seed %d sigma/q %.3f | incons %d suggested %d first %d (%s) points %d other %d "
        "| step_err %.2g N_err %.2f N/true %.3f | consistent_after %d (%.3g -> %.3g) | failing: "
        "%s | after: %s\n",
        name.c_str(), seed, s.sigma_over_q, s.inconsistent, s.suggested, s.first_right,
        s.first.c_str(), s.points, s.other_suggested, s.step_error, s.n_error, s.n_ratio,
        s.consistent_after, s.error_before, s.error_after, s.failures.c_str(),
        s.failures_after.c_str());
    std::fflush(stdout);
  }
}

}  // namespace
}  // namespace fogpipe::model
