// Tests algorithms/method/method.cpp on simulated recordings in the paper's setting
// (fogpipe::simulation::PaperOptions: 1 h at 1 Hz, navigation-grade N, B, K, Q; known truth),
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

TEST(Method, PrintsTables3And5OnPaperLikeData) {
  for (std::uint64_t seed : kSeeds) {
    const MethodResult& r = PaperResult(seed);
    ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
    std::printf("simulation::PaperOptions(seed %llu)\n%s%s\n",
                static_cast<unsigned long long>(seed), FormatTable3(Table3(r)).c_str(),
                FormatTable5(Table5(r)).c_str());
  }
}

// The shape of the paper's Table 3: every component's one-step fit is at or above the fit of
// the one AR model of the raw signal.
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
// than method 2). It does NOT hold with fogpipe's noise accounting on paper-profile data, and is
// kept disabled as a record of that (see schemas/results-v1.md and the graph report): the
// recordings are dominated by white noise (raw AR fit ~1 %), so with R from the white-noise level
// and q matched to the AR innovation variance (no double counting) method 2's filter tracks a
// near-constant and removes nearly everything (its N drops by 1e2..1e9), while method 1 keeps
// some high-frequency content; the raw fit finds K = 0 in one hour at 1 Hz, so a 10x drop of K
// is not measurable. PrintsTables3And5OnPaperLikeData shows the numbers.
TEST(Method, DISABLED_MethodOneLowersNAndKTenfoldAndMoreThanMethodTwo) {
  for (std::uint64_t seed : kSeeds) {
    const std::vector<NoiseRow> t = Table5(PaperResult(seed));
    EXPECT_LE(t[1].n_deg_sqrt_h, t[0].n_deg_sqrt_h / 10.0) << seed;
    EXPECT_LE(t[1].k_deg_h_sqrt_h, t[0].k_deg_h_sqrt_h / 10.0) << seed;
    EXPECT_LT(t[1].n_deg_sqrt_h, t[2].n_deg_sqrt_h) << seed;
    EXPECT_LT(t[1].k_deg_h_sqrt_h, t[2].k_deg_h_sqrt_h) << seed;
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
