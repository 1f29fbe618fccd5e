// Simulator throughput: the navigation profile at several lengths and rates, and its most
// expensive part alone (the whole-record FFT of Kasdin's flicker filter).
#include <benchmark/benchmark.h>

#include "algorithms/simulation/flicker_noise.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"

namespace fogpipe::simulation {
namespace {

// Arguments: duration in s, sample rate in Hz.
void BM_SimulateNavigationGrade(benchmark::State& state) {
  GyroSimulatorOptions options = NavigationGradeOptions(1);
  options.duration_s = static_cast<double>(state.range(0));
  options.sample_rate_hz = static_cast<double>(state.range(1));
  AddNavigationGradeTerm(Term::kSinusoid, 1, &options);
  AddNavigationGradeTerm(Term::kGaussMarkov, 1, &options);
  AddNavigationGradeTerm(Term::kTemperatureRate, 1, &options);
  for (auto _ : state) {
    SimulatedRecording r = SimulateGyro(options);
    benchmark::DoNotOptimize(r.rate_rad_s.data());
  }
  state.SetItemsProcessed(state.iterations() * options.NumSamples());
}
BENCHMARK(BM_SimulateNavigationGrade)
    ->Args({3600, 1})         // the paper's setting
    ->Args({6 * 3600, 10})    // the hidden-effect records of the compare tests
    ->Args({3600, 100})       // the sweep benchmark's record
    ->Args({24 * 3600, 100})  // the 24 h record of the pipeline benchmark
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_FlickerRateNoise(benchmark::State& state) {
  const Eigen::Index n = state.range(0);
  for (auto _ : state) {
    RandomSource rng(1);
    Eigen::VectorXd x = FlickerRateNoise(n, 10.0, 1e-8, &rng);
    benchmark::DoNotOptimize(x.data());
  }
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_FlickerRateNoise)
    ->Arg(216000)
    ->Arg(360000)
    ->Arg(8640000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace fogpipe::simulation

BENCHMARK_MAIN();
