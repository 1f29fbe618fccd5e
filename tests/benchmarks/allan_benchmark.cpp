// Speed of algorithms/allan (one thread unless the name says otherwise). Target: OADEV at 64
// log-spaced taus of 1e7 samples, confidence intervals included, <= 0.5 s (allantools: 3.6 s, 38 s
// with CIs). MDEV and TOTDEV on the octave grid of the first 1e6 and of all 1e7 samples (results:
// docs/allan-deviations.md).
//   build/tests/benchmarks/allan_benchmark --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/model_edf.h"
#include "algorithms/allan/noise_fit.h"

namespace fogpipe::allan {
namespace {

constexpr long long kSamples = 10'000'000;

// White rate noise plus a random walk (so that several noise types are identified), fixed seed.
const Eigen::VectorXd& Rate() {
  static const Eigen::VectorXd rate = [] {
    std::mt19937_64 engine(42);
    Eigen::VectorXd y(kSamples);
    double walk = 0.0;
    for (long long i = 0; i < kSamples; i += 2) {
      const double u1 = (static_cast<double>(engine() >> 11) + 1.0) * 0x1.0p-53;
      const double u2 = (static_cast<double>(engine() >> 11) + 1.0) * 0x1.0p-53;
      const double r = std::sqrt(-2.0 * std::log(u1)), phi = 6.283185307179586 * u2;
      walk += 1e-4 * r * std::sin(phi);
      y[i] = r * std::cos(phi) + walk;
      if (i + 1 < kSamples) y[i + 1] = r * std::sin(phi) + walk;
    }
    return y;
  }();
  return rate;
}

// Differenced white noise (white PM, quantization-like): every row is read as phase noise, so
// every EDF and the few-average laws come from phase_noise_law.h, the intervals' costliest path.
const Eigen::VectorXd& WhitePmRate() {
  static const Eigen::VectorXd rate = [] {
    std::mt19937_64 engine(43);
    std::normal_distribution<double> normal;
    Eigen::VectorXd y(kSamples);
    double previous = normal(engine);
    for (long long i = 0; i < kSamples; ++i) {
      const double x = normal(engine);
      y[i] = x - previous;
      previous = x;
    }
    return y;
  }();
  return rate;
}

// 64 distinct log-spaced averaging factors from 1 to the maximum.
std::vector<long long> LogSpacedFactors(long long max_m, int count) {
  for (int points = count;; ++points) {
    std::vector<long long> m;
    for (int j = 0; j < points; ++j) {
      const long long v = std::llround(std::pow(static_cast<double>(max_m), j / (points - 1.0)));
      if (m.empty() || v != m.back()) m.push_back(v);
    }
    if (static_cast<int>(m.size()) >= count) return m;
  }
}

void RunAllan(benchmark::State& state, Deviation deviation, bool ci,
              NoiseIdRule rule = NoiseIdRule::kCalibrated, int threads = 1,
              const Eigen::VectorXd& rate = Rate()) {
  AllanOptions options;
  options.threads = threads;
  options.noise_id = rule;
  options.deviation = deviation;
  options.confidence_intervals = ci;
  options.grid.kind = TauGridKind::kExplicit;
  options.grid.explicit_m = LogSpacedFactors(MaxAveragingFactor(deviation, kSamples), 64);
  for (auto _ : state) {
    AllanResult r = ComputeAllan(rate, 100.0, options);
    benchmark::DoNotOptimize(r.table.sigma.data());
    if (r.table.size() != 64) state.SkipWithError("grid is not 64 taus");
  }
  state.counters["taus"] = 64;
}

void BM_Oadev64TausWithCi(benchmark::State& s) { RunAllan(s, Deviation::kOverlappingAllan, true); }
// As `fogpipe allan` runs it on this 2-core machine (--threads defaults to the cores).
void BM_Oadev64TausWithCiTwoThreads(benchmark::State& s) {
  RunAllan(s, Deviation::kOverlappingAllan, true, NoiseIdRule::kCalibrated, 2);
}
// The Stable32 rule, for the cost of the calibrated rule's R(n) passes (noise_id.h).
void BM_Oadev64TausWithCiStable32Rule(benchmark::State& s) {
  RunAllan(s, Deviation::kOverlappingAllan, true, NoiseIdRule::kStable32);
}
void BM_Oadev64TausWithCiWhitePm(benchmark::State& s) {
  RunAllan(s, Deviation::kOverlappingAllan, true, NoiseIdRule::kCalibrated, 1, WhitePmRate());
}
void BM_Oadev64TausWithCiWhitePmTwoThreads(benchmark::State& s) {
  RunAllan(s, Deviation::kOverlappingAllan, true, NoiseIdRule::kCalibrated, 2, WhitePmRate());
}
void BM_Oadev64TausNoCi(benchmark::State& s) { RunAllan(s, Deviation::kOverlappingAllan, false); }
void BM_Adev64TausWithCi(benchmark::State& s) { RunAllan(s, Deviation::kAllan, true); }
void BM_Ohdev64TausWithCi(benchmark::State& s) {
  RunAllan(s, Deviation::kOverlappingHadamard, true);
}
void BM_Hdev64TausWithCi(benchmark::State& s) { RunAllan(s, Deviation::kHadamard, true); }

// The octave grid of the first state.range(0) samples; state.range(1) = 1: with intervals.
void RunOctave(benchmark::State& state, Deviation deviation) {
  const Eigen::VectorXd rate = Rate().head(state.range(0));
  AllanOptions options;
  options.deviation = deviation;
  options.confidence_intervals = state.range(1) == 1;
  for (auto _ : state) {
    AllanResult r = ComputeAllan(rate, 100.0, options);
    benchmark::DoNotOptimize(r.table.sigma.data());
    state.counters["taus"] = static_cast<double>(r.table.size());
  }
}

void BM_MdevOctave(benchmark::State& s) { RunOctave(s, Deviation::kModifiedAllan); }
void BM_TotdevOctave(benchmark::State& s) { RunOctave(s, Deviation::kTotal); }
void BM_OadevOctave(benchmark::State& s) { RunOctave(s, Deviation::kOverlappingAllan); }

void BM_FitNoiseTermsOctave(benchmark::State& state) {
  AllanOptions options;
  const AllanTable table = ComputeAllan(Rate(), 100.0, options).table;
  for (auto _ : state) {
    NoiseFitResult f = FitNoiseTerms(table, NoiseFitOptions());
    benchmark::DoNotOptimize(f.chi2);
  }
}

// The fit at 100 log-spaced taus (target <= 50 ms): the generalised fit with its covariance lag
// sums (avar_covariance.h). "Rejected": the same record plus a 0.5 Hz sinusoid the five-term
// model cannot describe, so the model-discrepancy search runs too.
void RunFit100(benchmark::State& state, double sine_amplitude, bool model_edf = false) {
  Eigen::VectorXd rate = Rate();
  for (long long i = 0; i < kSamples; ++i)
    rate[i] += sine_amplitude * std::sin(6.283185307179586 * 0.5 * static_cast<double>(i) / 100.0);
  AllanOptions options;
  options.grid.kind = TauGridKind::kExplicit;
  options.grid.explicit_m =
      LogSpacedFactors(MaxAveragingFactor(Deviation::kOverlappingAllan, kSamples), 100);
  const AllanTable table = ComputeAllan(rate, 100.0, options).table;
  if (table.size() != 100) state.SkipWithError("grid is not 100 taus");
  NoiseFitResult f;
  for (auto _ : state) {
    if (model_edf) {
      AllanTable t = table;
      f = FitNoiseTermsAndModelEdf(NoiseFitOptions(), options.confidence, &t);
      benchmark::DoNotOptimize(t.ci_low.data());
    } else {
      f = FitNoiseTerms(table, NoiseFitOptions());
    }
    benchmark::DoNotOptimize(f.chi2);
  }
  state.counters["discrepancy"] = f.model_discrepancy;
}
void BM_FitNoiseTerms100Taus(benchmark::State& s) { RunFit100(s, 0.0); }
void BM_FitNoiseTerms100TausRejected(benchmark::State& s) { RunFit100(s, 0.3); }
// The fit and the model's intervals (model_edf.h), as `allan` and `run` make them.
void BM_FitNoiseTermsAndModelEdf100Taus(benchmark::State& s) { RunFit100(s, 0.0, true); }

BENCHMARK(BM_Oadev64TausWithCi)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Oadev64TausWithCiWhitePm)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Oadev64TausWithCiWhitePmTwoThreads)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Oadev64TausWithCiTwoThreads)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Oadev64TausWithCiStable32Rule)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Oadev64TausNoCi)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Adev64TausWithCi)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Ohdev64TausWithCi)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Hdev64TausWithCi)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MdevOctave)
    ->ArgsProduct({{1'000'000, kSamples}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_TotdevOctave)
    ->ArgsProduct({{1'000'000, kSamples}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_OadevOctave)
    ->ArgsProduct({{1'000'000, kSamples}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_FitNoiseTermsOctave)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FitNoiseTerms100Taus)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitNoiseTermsAndModelEdf100Taus)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FitNoiseTerms100TausRejected)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace fogpipe::allan

BENCHMARK_MAIN();
