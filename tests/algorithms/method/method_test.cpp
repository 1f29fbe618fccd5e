// Tests algorithms/method/method.cpp on simulated recordings in the paper's setting
// (fogpipe::simulation::PaperOptions: 1 h at 1 Hz, navigation-grade N, B, K, Q; PaperDriftOptions:
// the same with Table 5's raw K/N and B/N; known truth),
// and on closed-form properties of the stages.
#include "algorithms/method/method.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "algorithms/method/tables.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"

namespace fogpipe::method {
namespace {

constexpr std::uint64_t kSeeds[] = {1, 2, 3};

Eigen::VectorXd PaperRecording(std::uint64_t seed) {
  const simulation::SimulatedRecording rec =
      simulation::SimulateGyro(simulation::PaperOptions(seed));
  EXPECT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
  return rec.rate_rad_s;
}

const MethodResult& PaperResult(std::uint64_t seed) {
  static std::map<std::uint64_t, MethodResult> cache;
  auto it = cache.find(seed);
  if (it == cache.end()) {
    it = cache.emplace(seed, RunMethod(PaperRecording(seed), 1.0, MethodOptions())).first;
  }
  return it->second;
}

// The paper's raw character (simulation::PaperDriftOptions: Table 5's K/N and B/N, rate random
// walk dominating beyond ~15 s) with the paper's fixed AR(6) for method 2; defaults otherwise.
const MethodResult& PaperDriftResult(std::uint64_t seed) {
  static std::map<std::uint64_t, MethodResult> cache;
  auto it = cache.find(seed);
  if (it == cache.end()) {
    const simulation::SimulatedRecording rec =
        simulation::SimulateGyro(simulation::PaperDriftOptions(seed));
    EXPECT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
    MethodOptions options;
    options.direct_ar_order = 6;  // the paper's direct AR(6) (method.md, Table 3)
    it = cache.emplace(seed, RunMethod(rec.rate_rad_s, 1.0, options)).first;
  }
  return it->second;
}

void PrintTables(const char* profile, const MethodResult& (*result)(std::uint64_t)) {
  for (std::uint64_t seed : kSeeds) {
    const MethodResult& r = result(seed);
    ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
    std::printf("simulation::%s(seed %llu)\n%s%s\n", profile, static_cast<unsigned long long>(seed),
                FormatTable3(Table3(r)).c_str(), FormatTable5(Table5(r)).c_str());
  }
}

TEST(Method, PrintsTables3And5OnPaperLikeData) { PrintTables("PaperOptions", PaperResult); }

TEST(Method, PrintsTables3And5OnPaperDriftDataWithMethodTwoAr6) {
  PrintTables("PaperDriftOptions", PaperDriftResult);
}

// The shape of the paper's Table 3: every component's one-step fit is at or above the fit of
// the one AR model of the raw signal. It holds on PaperOptions (nearly white, raw fit ~1 %), not
// on PaperDriftOptions: there the raw AR(6) fits 22..57 % but imf1, EMD's highest-frequency mode
// of the white floor, fits 13..15 % (imf2 60..62 %, imf3 92..93 %, imf4 99.1..99.2 %). The paper's
// own Table 2 coefficients agree with us, not with its Table 3: their stationary one-step fits,
// 1 - sqrt(sigma_e^2 / var), are imf1 11.3 %, imf2 54.9 %, imf3 90.83 %, imf4 98.62 % (imf3 and
// imf4 equal the printed Table 3; imf1 and imf2 are printed as 85.47 and 87.65). So a raw record
// as coloured as the printed 74.66 % with a white floor cannot have imf1 fit above it.
TEST(Method, EveryComponentFitsAtLeastAsWellAsTheRawModel) {
  for (std::uint64_t seed : kSeeds) {
    const MethodResult& r = PaperResult(seed);
    ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
    const double raw = r.direct.fit.diagnostics.fit_one_step_percent;
    const int n = static_cast<int>(r.components.size()) - 1;
    ASSERT_GE(n, 5) << "EMD of 3600 samples of noise gives about log2(3600) - 1 IMFs";
    for (int k = 0; k <= n; ++k) {
      EXPECT_GE(r.components[k].fit.diagnostics.fit_one_step_percent, raw)
          << "seed " << seed << " " << ComponentName(k, n);
    }
  }
}

// Eq. 12 and the decomposition hold exactly: the stored pieces add up.
TEST(Method, ReconstructionIsTheSumOfTheFilteredComponentsInOrder) {
  const MethodResult& r = PaperResult(1);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(r.method1.size());
  for (const ComponentModel& c : r.components) sum += c.Output();
  EXPECT_EQ((sum - r.method1).cwiseAbs().maxCoeff(), 0.0);
  Eigen::VectorXd parts = r.decomposition.residue;
  for (const auto& imf : r.decomposition.imfs) parts += imf;
  // EMD's residue is x minus the IMFs: adding them back costs one rounding per IMF.
  const double scale = r.preprocessed.signal.cwiseAbs().maxCoeff();
  EXPECT_LE((parts - r.preprocessed.signal).cwiseAbs().maxCoeff(), 1e-13 * scale);
}

// The result must not depend on how the per-component loop is scheduled.
TEST(Method, ReverseOrderScheduleGivesIdenticalNumbers) {
  const Eigen::VectorXd x = PaperRecording(2);
  const MethodResult a = RunMethod(x, 1.0, MethodOptions());
  const MethodResult b = RunMethod(x, 1.0, MethodOptions(), [](int n, const auto& body) {
    for (int i = n - 1; i >= 0; --i) body(i);
  });
  EXPECT_TRUE(a.method1 == b.method1);
  EXPECT_TRUE(a.direct.Output() == b.direct.Output());
  EXPECT_EQ(a.method1_allan.allan.table.sigma, b.method1_allan.allan.table.sigma);
}

// The shape of the paper's Table 5 (method 1 lowers N and K by >= 10x against raw, and more
// than method 2). It does NOT hold with fogpipe's default settings, on either profile, and is kept
// disabled as the record of that (issue 3 asks for it; an honest negative beats a tuned positive).
// It runs on the faithful setting: PaperDriftOptions (Table 5's raw K/N and B/N, so raw K is
// measurable in 1 h) with the paper's AR(6) for method 2. Measured (seeds 1, 2, 3; raw -> m1, m2):
//   N deg/sqrt(h): 2.95e-3 -> 3.87e-4, 0 | 6.09e-3 -> 2.02e-3, 0 | 7.30e-3 -> 1.73e-2, 0
//   K deg/h^1.5:   0.899   -> 0.284, 0.124 | 2.67 -> 0.528, 0.0472 | 2.99 -> 1.27, 1.45
// so method 1 scales N by 0.13..2.4 and K by 0.20..0.43, and method 2 lowers N further (to below
// what the fit resolves) and K further on 2 of 3 seeds. Neither output is a filtered signal,
// though: with the default noise rule every component filter of method 1 (64 of 64: 3 seeds, both
// profiles) gets q = 0 (DISABLED_EveryComponentFilterGetsPositiveProcessNoise), so the gain decays
// to 0 and each "filtered" IMF is its AR model's free response from X0 = 0: the fast IMFs come out
// ~0 (variance 1e-6..1e-3 of the input's) and slow ones run off (drift seed 3: imf9's output
// variance is 2.7x its input's, 1.9x the whole signal's). Method 1's N and K above are
// those artefacts; method 2's N = 0 is the same clamp (q = 0 on PaperOptions, q = 0.002..0.03
// sigma_e^2 here: bandwidth narrowing, method.md "What to keep in mind"). Table 5 cannot be judged
// until the noise rule gives the filters a positive q. A one-off run (not the defaults, not
// committed) with the paper-style q = sigma_e^2 per component and R = its white share, = sigma_e^2
// or = 0.1 x share (drift seeds 1..5) gives filters that track: method 1 keeps K (x0.48..x1.01)
// and lowers N only x0.50..x0.95, method 2 lowers N more (x0.22..x0.91). A filter that tracks the
// signal cannot remove a rate random walk, which is signal to its AR model, so a 10x drop of K
// points at over-smoothing, not at a better estimate. On PaperOptions (navigation-grade, nearly
// white; raw fit ~1 %) the raw fit finds K = 0 in 1 h, so a 10x drop of K is not even measurable
// there (PrintsTables3And5OnPaperLikeData).
TEST(Method, DISABLED_MethodOneLowersNAndKTenfoldAndMoreThanMethodTwo) {
  for (std::uint64_t seed : kSeeds) {
    const std::vector<NoiseRow> t = Table5(PaperDriftResult(seed));
    EXPECT_LE(t[1].n_deg_sqrt_h, t[0].n_deg_sqrt_h / 10.0) << seed;
    EXPECT_LE(t[1].k_deg_h_sqrt_h, t[0].k_deg_h_sqrt_h / 10.0) << seed;
    EXPECT_LT(t[1].n_deg_sqrt_h, t[2].n_deg_sqrt_h) << seed;
    EXPECT_LT(t[1].k_deg_h_sqrt_h, t[2].k_deg_h_sqrt_h) << seed;
  }
}

// The default noise rule (method/white_noise.h + kalman/noise_defaults.h) solves for q with
// S(q) = sigma_e^2 and clamps q to 0 when sigma_e^2 <= R. For an IMF that always happens: its R is
// its share of the raw white-noise variance (capped at its own variance), but EMD turns that share
// into a band-limited, hence predictable, signal, so the IMF's one-step innovation sigma_e^2 is far
// below it (measured, PaperDriftOptions seed 1: imf1 sigma_e^2 0.26 vs R 0.31, imf3 2.8e-4 vs
// 5.4e-2, imf9 3.3e-18 vs 8.6e-4, in units of the raw variance; the same on PaperOptions). With
// q = 0 the filter ignores its data once the gain has decayed. Kept disabled as the tripwire for
// whoever changes the rule (owners: method/white_noise, kalman/noise_defaults).
TEST(Method, DISABLED_EveryComponentFilterGetsPositiveProcessNoise) {
  for (std::uint64_t seed : kSeeds) {
    for (const MethodResult* r : {&PaperResult(seed), &PaperDriftResult(seed)}) {
      const int n = static_cast<int>(r->components.size()) - 1;
      for (int k = 0; k <= n; ++k) {
        EXPECT_GT(r->components[k].kalman.q, 0.0) << "seed " << seed << " " << ComponentName(k, n);
      }
    }
  }
}

TEST(Method, ReportsTheStageThatFailed) {
  MethodResult r = RunMethod(Eigen::VectorXd::Constant(600, 1e-5), 1.0, MethodOptions());
  EXPECT_FALSE(HasResult(r.summary.termination));
  EXPECT_NE(r.summary.message.find("preprocessing"), std::string::npos) << r.summary.message;
  MethodOptions bad;
  bad.direct_ar_order = -1;
  r = RunMethod(PaperRecording(1), 1.0, bad);
  EXPECT_EQ(r.summary.termination, Termination::kInvalidOptions);
}

}  // namespace
}  // namespace fogpipe::method
