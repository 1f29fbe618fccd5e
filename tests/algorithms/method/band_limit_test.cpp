// Tests algorithms/method/band_limit.cpp: the split keeps the sum, removes each component's content
// below its band (measured by a direct DFT, independent of the filter), and makes method 1 keep the
// long-tau Allan deviation of static records (statement S2 below), on test seeds apart from
// the design seeds the ratio was chosen on (docs/filtering.md).
#include "algorithms/method/band_limit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "algorithms/allan/allan.h"
#include "algorithms/emd/emd.h"
#include "algorithms/method/method.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::method {
namespace {

// White noise plus a slow random walk: IMFs over many octaves.
Eigen::VectorXd NoisyRecord(Eigen::Index n, std::uint64_t seed) {
  simulation::RandomSource normal(seed);
  Eigen::VectorXd x(n);
  double walk = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    walk += 0.02 * normal.Normal();
    x[i] = normal.Normal() + walk;
  }
  return x;
}

// Fraction of x's energy (mean removed) at DFT frequencies strictly below `cutoff` cycles per
// sample, by a direct DFT (no filter, no FFT library).
double FractionBelow(const Eigen::VectorXd& x, double cutoff) {
  const Eigen::Index n = x.size();
  const Eigen::VectorXd c = x.array() - x.mean();
  const double total = c.squaredNorm() * static_cast<double>(n);  // Parseval: sum |X_j|^2
  double below = 0.0;
  for (Eigen::Index j = 1; static_cast<double>(j) / n < cutoff && j < n / 2; ++j) {
    std::complex<double> sum = 0.0;
    const double w = -2.0 * M_PI * static_cast<double>(j) / static_cast<double>(n);
    for (Eigen::Index t = 0; t < n; ++t) sum += c[t] * std::polar(1.0, w * static_cast<double>(t));
    below += 2.0 * std::norm(sum);  // bins j and n - j
  }
  return below / total;
}

TEST(BandLimit, KeepsTheSumOfTheComponents) {
  const Eigen::VectorXd x = NoisyRecord(8192, 31);
  emd::EmdResult d = emd::Decompose(x, emd::EmdOptions());
  ASSERT_GE(d.imfs.size(), 8u);
  Eigen::VectorXd before = d.residue;
  for (const auto& imf : d.imfs) before += imf;
  BandLimitImfs(BandLimitOptions(), &d);
  Eigen::VectorXd after = d.residue;
  for (const auto& imf : d.imfs) after += imf;
  EXPECT_LT((after - before).cwiseAbs().maxCoeff(), 1e-12 * x.cwiseAbs().maxCoeff());
}

// Each component keeps at most 5 % of its energy an octave below its cutoff (cutoff_ratio / T_k,
// T_k its mean period as split and stored; there the order-4 forward-backward response is
// 1 / (1 + 2^8) and falls as f^8 further down), where EMD's own IMFs carry several times more.
TEST(BandLimit, LeavesEachComponentLittleOfItsEnergyBelowItsBand) {
  const Eigen::Index n = 4096;
  const Eigen::VectorXd x = NoisyRecord(n, 32);
  const emd::EmdResult original = emd::Decompose(x, emd::EmdOptions());
  emd::EmdResult limited = original;
  const BandLimitOptions options;
  BandLimitImfs(options, &limited);
  int checked = 0;
  double sum_before = 0.0, sum_after = 0.0;
  for (std::size_t k = 0; k < original.imfs.size(); ++k) {
    const double period = limited.imf_info[k].mean_period_samples;
    if (static_cast<double>(n) / period < 32.0) break;  // enough DFT bins below the cutoff
    const double cutoff = 0.5 * options.cutoff_ratio / period;
    const double before = FractionBelow(original.imfs[k], cutoff);
    const double after = FractionBelow(limited.imfs[k], cutoff);
    std::printf("imf%zu: T %.1f samples, energy below %.4f cycles/sample %.3f -> %.3f\n", k + 1,
                period, cutoff, before, after);
    EXPECT_LT(after, 0.05) << "imf" << k + 1;
    sum_before += before;
    sum_after += after;
    ++checked;
  }
  EXPECT_GE(checked, 5);
  // EMD's own IMFs must leak for the test to test the split.
  EXPECT_GT(sum_before, 3.0 * sum_after);
}

// Statement S2 (docs/filtering.md): on static records, OADEV(method 1) <= 1.05 OADEV(raw) at every
// tau up to a quarter of the record in at least 95 % of seeds, for the paper's profile (1 h at 1
// Hz) and the navigation profile (6 h at 10 Hz), 20 seeds each (test seeds 301-320; the ratio was
// chosen on seeds 5000+ and 7000+). The EMD's own IMFs (cutoff_ratio 0) are run too and must fail
// it, or the test would not show what the split does.
TEST(BandLimit, MethodOneKeepsTheLongTauAllanDeviationOfStaticRecords) {
  struct Profile {
    const char* name;
    simulation::GyroSimulatorOptions (*options)(std::uint64_t);
  };
  for (const Profile& profile : {Profile{"paper", simulation::PaperOptions},
                                 Profile{"navigation", simulation::NavigationGradeOptions}}) {
    int within[2] = {0, 0}, k_above = 0;
    double worst[2] = {0.0, 0.0};
    const int seeds = 20;
    for (int s = 0; s < seeds; ++s) {
      const simulation::SimulatedRecording rec = simulation::SimulateGyro(profile.options(301 + s));
      ASSERT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
      const double fs = profile.options(301 + s).sample_rate_hz;
      for (int variant = 0; variant < 2; ++variant) {
        MethodOptions options;
        if (variant == 1) options.band_limit.cutoff_ratio = 0.0;
        options.reference.enabled = false;  // method 1 alone is compared here
        MethodResult r;
        DecomposeAndModel(rec.rate_rad_s, fs, options, StreamOptions(), &r);
        ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
        allan::AllanOptions allan_options;
        allan_options.confidence_intervals = false;
        const allan::AllanResult raw =
            allan::ComputeAllan(r.preprocessed.signal, fs, allan_options);
        const allan::AllanResult m1 = allan::ComputeAllan(r.method1, fs, allan_options);
        const double quarter_s = 0.25 * static_cast<double>(r.method1.size()) / fs;
        double ratio = 0.0;
        for (std::size_t i = 0; i < raw.table.size(); ++i) {
          if (raw.table.tau_s[i] > quarter_s) break;
          ratio = std::max(ratio, m1.table.sigma[i] / raw.table.sigma[i]);
        }
        within[variant] += ratio <= 1.05;
        if (variant == 0) {
          // Every method-1 term above the raw fit's upper limit is flagged (EvaluateAllan).
          EvaluateAllan(fs, options, SerialForEach, &r);
          const double k = r.method1_allan.noise.terms.k_rad_s_sqrt_s;
          const double limit = r.raw_allan.noise.assessment[3].upper_limit;
          if (std::isfinite(limit) && k > limit) {
            ++k_above;
            EXPECT_FALSE(r.method1_allan.noise.assessment[3].reliable);
          }
        }
        worst[variant] = std::max(worst[variant], ratio);
      }
    }
    std::printf(
        "%s: OADEV(method 1) / OADEV(raw) <= 1.05 at every tau <= T/4 in %d of %d seeds "
        "(worst %.3f); with EMD's own IMFs %d of %d (worst %.3f)\n",
        profile.name, within[0], seeds, worst[0], within[1], seeds, worst[1]);
    std::printf("%s: method 1's K above the raw fit's upper limit (so flagged) in %d of %d seeds\n",
                profile.name, k_above, seeds);
    EXPECT_GE(within[0], 19) << profile.name;  // 95 % of 20
    EXPECT_LT(within[1], 19) << profile.name;
  }
}

}  // namespace
}  // namespace fogpipe::method
