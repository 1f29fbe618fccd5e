#include "algorithms/kalman/ar_filter_bank.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <utility>

#include "tests/algorithms/kalman/filter_options.h"
#include "tests/algorithms/kalman/paper_models.h"
#include "tests/algorithms/kalman/simulate_ar.h"

namespace fogpipe::kalman {
namespace {

using testing::PaperStart;
using testing::PaperTable2Models;
using testing::Phi;
using testing::SimulateArPlusNoise;
using testing::SteadyStart;

// The sweep's batch entry: several option sets on one model, outputs added to sums. Each sum must
// equal FilterAr's output for the same options (steady-state lanes run side by side, 4 at a time,
// the rest through FilterAr's own path); the same arithmetic per lane in the same order, so equal
// to the last bit (the sums start at 1, so the reference is 1 + FilterAr's output).
TEST(FilterArAndAdd, EachSumEqualsFilterArForItsOptions) {
  const auto models = PaperTable2Models();
  // Orders 1 and 4 (fixed kernels up to 8), 11 (the sweep's 9..12 kernels) and 40 (one lane at a
  // time above the side-by-side limit); 11 and 40 are imf3's model padded with zeros.
  Eigen::VectorXd padded11 = Eigen::VectorXd::Zero(11), padded40 = Eigen::VectorXd::Zero(40);
  padded11.head(4) = models[2].phi;
  padded40.head(4) = models[2].phi;
  for (const Eigen::VectorXd& model : {Phi({0.9}), models[1].phi, padded11, padded40}) {
    const testing::ArSimulation sim = SimulateArPlusNoise(model, 0.1, 1.0, 5000, 111);
    std::vector<ArKalmanOptions> options;
    for (double q : {0.01, 0.1, 1.0})
      for (double r : {0.5, 1.0, 2.0}) options.push_back(SteadyStart(q, r));
    options.push_back(PaperStart(0.1, 1.0));  // through FilterAr's time-varying path
    options.back().mean = 0.25;
    std::vector<Eigen::VectorXd> sums(options.size(), Eigen::VectorXd::Constant(5000, 1.0));
    std::vector<double*> pointers;
    for (auto& v : sums) pointers.push_back(v.data());
    const std::vector<ArKalmanSummary> summaries =
        FilterArAndAdd(sim.z, model, -1, -1, options, pointers);
    ASSERT_EQ(summaries.size(), options.size());
    for (std::size_t i = 0; i < options.size(); ++i) {
      const ArKalmanResult single = FilterAr(sim.z, model, -1, -1, options[i]);
      ASSERT_EQ(summaries[i].termination, Termination::kSuccess) << summaries[i].message;
      EXPECT_EQ(summaries[i].gain_switch, single.summary.gain_switch);
      EXPECT_EQ((sums[i].array() - (1.0 + single.filtered.array())).abs().maxCoeff(), 0.0)
          << "p = " << model.size() << " option set " << i;
    }
  }
}

// The sweep's bank (ArFilterBank) against FilterAr alone, option set by option set, to the last
// bit: the time-varying phases run FilterAr's code, each filter then continues alone to the latest
// switch and side by side from there, in ranges, with the same arithmetic in the same order.
// Models: a unit root (random walk) and the paper's residue (roots 1 and 0.9989), the
// near-unit-root imf6 and imf7, an explosive AR(1) and the paper's slightly explosive imf9 (root
// modulus 1.00025), a stable AR(1), and imf3 padded with zeros to every order 5..13 (the
// fixed-order lane kernels 9..12 and the runtime-order one). Option sets: the paper's start over a
// q/R grid with the sweep's 4096-step cap (capped and converged switches), q/R = 1e-10 uncapped
// (stalled on the residue), the steady-state start, q = 0 from P(0|0) = 0 (gain 0), q = 0 from the
// paper's start (on a unit root: frozen or never switching), and the smoother (computed whole).
TEST(ArFilterBank, EachOutputEqualsFilterArToTheLastBitOnUnitNearUnitAndExplosiveRoots) {
  const auto paper = PaperTable2Models();
  std::vector<std::pair<const char*, Eigen::VectorXd>> models = {
      {"random walk", Phi({1.0})}, {"residue", paper[8].phi},         {"imf6", paper[5].phi},
      {"imf7", paper[6].phi},      {"explosive AR(1)", Phi({1.002})}, {"imf9", paper[7].phi},
      {"AR(1) 0.5", Phi({0.5})}};
  for (int p = 5; p <= 13; ++p) {
    Eigen::VectorXd padded = Eigen::VectorXd::Zero(p);
    padded.head(4) = paper[2].phi;
    models.push_back({"imf3 padded", padded});
  }
  // A random walk observed in white noise: bounded enough for every model above over 12000
  // samples, and a slow signal as the slow IMFs are.
  const long long n = 12000;
  const testing::ArSimulation sim = SimulateArPlusNoise(Phi({1.0}), 0.01, 1.0, n, 7, 0);
  const Eigen::VectorXd z = sim.z.array() + 0.5;
  std::map<GainSwitch, int> seen;
  for (const auto& [name, phi] : models) {
    std::vector<ArKalmanOptions> options;
    for (double q : {1e-4, 0.01, 1.0}) {
      for (double r : {0.1, 1.0, 10.0}) {
        options.push_back(PaperStart(q, r));
        options.back().max_time_varying_steps = 4096;
      }
    }
    options.push_back(SteadyStart(0.01, 1.0));
    // No cap: the stall rule (the residue, imf6). Whether a given model stalls or converges
    // depends on where in its rounding noise the gain distance falls, which differs between
    // builds with and without fused multiply-adds: several tiny q so that some stall in either.
    for (double q : {1e-12, 1e-11, 1e-10, 1e-9}) {
      options.push_back(PaperStart(q, 1.0));
      options.back().max_time_varying_steps = 0;
    }
    options.push_back(PaperStart(0.0, 1.0));
    options.back().initial_variance = 0.0;
    options.push_back(PaperStart(0.0, 1.0));
    options.back().max_time_varying_steps = 4096;
    options.push_back(PaperStart(0.01, 1.0));
    options.back().smooth = true;
    for (ArKalmanOptions& o : options) o.mean = 0.5;
    const std::vector<ArKalmanOptions> all_options = options;
    for (std::size_t count : {std::size_t(1), std::size_t(2), std::size_t(3), std::size_t(6),
                              std::size_t(10), all_options.size()}) {
      options.assign(all_options.begin(), all_options.begin() + count);
      std::vector<Eigen::VectorXd> sums(options.size(), Eigen::VectorXd::Constant(n, 1.0));
      std::vector<double*> pointers;
      for (auto& v : sums) pointers.push_back(v.data());
      ArFilterBank bank(z, phi, -1, -1, options);
      for (long long begin = 0; begin < n; begin += 777) {
        bank.AddRange(begin, std::min(n, begin + 777), pointers);
      }
      const std::vector<ArKalmanSummary> summaries = bank.summaries();
      ASSERT_EQ(summaries.size(), options.size());
      for (std::size_t i = 0; i < options.size(); ++i) {
        const ArKalmanResult single = FilterAr(z, phi, -1, -1, options[i]);
        ++seen[single.summary.gain_switch];
        EXPECT_EQ(summaries[i].termination, single.summary.termination) << name << " set " << i;
        EXPECT_EQ(summaries[i].message, single.summary.message) << name << " set " << i;
        EXPECT_EQ(summaries[i].gain_switch, single.summary.gain_switch) << name << " set " << i;
        EXPECT_EQ(summaries[i].switched_at_sample, single.summary.switched_at_sample);
        if (!HasResult(single.summary.termination)) {
          EXPECT_EQ((sums[i].array() - 1.0).abs().maxCoeff(), 0.0) << "a failed sum is untouched";
          continue;
        }
        const Eigen::VectorXd& out = options[i].smooth ? single.smoothed : single.filtered;
        EXPECT_EQ((sums[i].array() - (1.0 + out.array())).abs().maxCoeff(), 0.0)
            << name << " p = " << phi.size() << " option set " << i << " ("
            << ToString(single.summary.gain_switch) << " at " << single.summary.switched_at_sample
            << ")";
      }
    }
  }
  // Every way of reaching (or not reaching) the constant-gain loop was exercised.
  for (GainSwitch kind : {GainSwitch::kNever, GainSwitch::kFromStart, GainSwitch::kConverged,
                          GainSwitch::kStalled, GainSwitch::kCapped, GainSwitch::kFrozen}) {
    EXPECT_GT(seen[kind], 0) << ToString(kind);
  }
}

// The bank's divergence statistic (EstimateMeanSquares, read by the sweep) is the mean of
// (estimate - mean)^2 of each output over the samples added, heads and side-by-side lanes alike:
// against the same sum over FilterAr's output (summed in another order: 1e-12 relative). And a
// bank given z's variance from FilterInputVariance (as the sweep does once per component) is the
// bank that computes it itself, to the last bit.
TEST(ArFilterBank, ReportsEachEstimatesMeanSquareAndTakesAGivenVariance) {
  const auto paper = PaperTable2Models();
  const long long n = 9000;
  const testing::ArSimulation sim = SimulateArPlusNoise(paper[5].phi, 0.01, 1.0, n, 12, 0);
  std::vector<ArKalmanOptions> options;
  for (double q : {1e-4, 0.01, 1.0}) {
    for (double r : {0.1, 1.0, 10.0}) {
      options.push_back(PaperStart(q, r));
      options.back().max_time_varying_steps = 4096;
      options.back().mean = 0.3;
    }
  }
  double z_variance = 0.0;
  ASSERT_TRUE(FilterInputVariance(sim.z, &z_variance));
  std::vector<Eigen::VectorXd> sums(options.size(), Eigen::VectorXd::Zero(n)), given = sums;
  std::vector<double*> pointers, given_pointers;
  for (std::size_t i = 0; i < options.size(); ++i) {
    pointers.push_back(sums[i].data());
    given_pointers.push_back(given[i].data());
  }
  ArFilterBank bank(sim.z, paper[5].phi, -1, -1, options);
  ArFilterBank given_bank(sim.z, paper[5].phi, -1, -1, options, &z_variance);
  for (long long begin = 0; begin < n; begin += 1000) {
    bank.AddRange(begin, std::min(n, begin + 1000), pointers);
    given_bank.AddRange(begin, std::min(n, begin + 1000), given_pointers);
  }
  const std::vector<double> mean_squares = bank.EstimateMeanSquares();
  for (std::size_t i = 0; i < options.size(); ++i) {
    const ArKalmanResult single = FilterAr(sim.z, paper[5].phi, -1, -1, options[i]);
    ASSERT_TRUE(HasResult(single.summary.termination));
    const double expected = (single.filtered.array() - 0.3).square().mean();
    EXPECT_NEAR(mean_squares[i], expected, 1e-12 * expected) << "option set " << i;
    EXPECT_EQ((given[i] - sums[i]).cwiseAbs().maxCoeff(), 0.0) << "option set " << i;
  }
}

// Sums interleaved sample by sample (as the sweep keeps them: setting i's sample k at k * count +
// i), which the bank adds four lanes at a time with vector operations, receive exactly what
// separate sums receive, also when only the current range is kept: 9 option sets (two interleaved
// groups of four and one left over, plus a smoother computed whole) on imf3 padded to order 11, in
// uneven ranges.
TEST(ArFilterBank, InterleavedSumsGetTheSameBitsAsSeparateOnes) {
  const auto paper = PaperTable2Models();
  Eigen::VectorXd phi = Eigen::VectorXd::Zero(11);
  phi.head(4) = paper[2].phi;
  const long long n = 7000;
  const testing::ArSimulation sim = SimulateArPlusNoise(phi, 0.1, 1.0, n, 13, 0);
  std::vector<ArKalmanOptions> options;
  for (double q : {0.01, 0.1, 1.0}) {
    for (double r : {0.5, 1.0, 2.0}) {
      options.push_back(PaperStart(q, r));
      options.back().max_time_varying_steps = 4096;
    }
  }
  options[4].smooth = true;
  const long long count = static_cast<long long>(options.size());
  std::vector<Eigen::VectorXd> separate(options.size(), Eigen::VectorXd::Constant(n, 0.5));
  Eigen::VectorXd interleaved = Eigen::VectorXd::Constant(n * count, 0.5);
  std::vector<double*> separate_pointers, interleaved_pointers;
  for (long long i = 0; i < count; ++i) {
    separate_pointers.push_back(separate[i].data());
    interleaved_pointers.push_back(interleaved.data() + i);
  }
  // A third bank adds into a buffer holding only the current range (sum_origin = the range's
  // start), copied out after each range, as the sweep keeps its sums.
  constexpr long long kRange = 1234;
  std::vector<double> range_buffer(static_cast<std::size_t>(kRange * count));
  std::vector<double*> range_pointers;
  for (long long i = 0; i < count; ++i) range_pointers.push_back(range_buffer.data() + i);
  Eigen::VectorXd from_ranges = Eigen::VectorXd::Constant(n * count, 0.5);
  ArFilterBank a(sim.z, phi, -1, -1, options), b(sim.z, phi, -1, -1, options),
      c(sim.z, phi, -1, -1, options);
  for (long long begin = 0; begin < n; begin += kRange) {
    const long long end = std::min(n, begin + kRange);
    a.AddRange(begin, end, separate_pointers);
    b.AddRange(begin, end, interleaved_pointers, count);
    std::copy(from_ranges.data() + begin * count, from_ranges.data() + end * count,
              range_buffer.begin());
    c.AddRange(begin, end, range_pointers, count, begin);
    std::copy(range_buffer.begin(), range_buffer.begin() + (end - begin) * count,
              from_ranges.data() + begin * count);
  }
  for (long long i = 0; i < count; ++i) {
    const Eigen::VectorXd taken = Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<>>(
        interleaved.data() + i, n, Eigen::InnerStride<>(count));
    const Eigen::VectorXd taken_from_ranges =
        Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<>>(from_ranges.data() + i, n,
                                                                   Eigen::InnerStride<>(count));
    EXPECT_EQ((taken - separate[i]).cwiseAbs().maxCoeff(), 0.0) << "option set " << i;
    EXPECT_EQ((taken_from_ranges - separate[i]).cwiseAbs().maxCoeff(), 0.0) << "option set " << i;
  }
}

}  // namespace
}  // namespace fogpipe::kalman
