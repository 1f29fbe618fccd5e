// Speed of the reference filters with their truth-free tuning (GCV, maximum likelihood) on one
// axis of 24 h at 100 Hz: white noise plus a slow sine. `run` runs the three tunings side by
// side (reference_filters.h), so its wall time is about the slowest one's.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "algorithms/filters/reference_filters.h"

namespace {

const Eigen::VectorXd& Record() {
  static const Eigen::VectorXd x = [] {
    const Eigen::Index n = 8640000;
    std::mt19937_64 rng(5);
    std::normal_distribution<double> g;
    Eigen::VectorXd v(n);
    for (Eigen::Index i = 0; i < n; ++i) v[i] = std::sin(2e-5 * static_cast<double>(i)) + g(rng);
    return v;
  }();
  return x;
}

void BM_Butterworth(benchmark::State& state) {
  for (auto _ : state) {
    auto r = fogpipe::filters::ZeroPhaseButterworth(Record(), 100.0, {});
    benchmark::DoNotOptimize(r.output.data());
  }
}
void BM_MovingAverage(benchmark::State& state) {
  for (auto _ : state) {
    auto r = fogpipe::filters::MovingAverage(Record(), {});
    benchmark::DoNotOptimize(r.output.data());
  }
}
void BM_RandomWalkKalman(benchmark::State& state) {
  for (auto _ : state) {
    auto r = fogpipe::filters::RandomWalkKalman(Record(), {});
    benchmark::DoNotOptimize(r.smoothed.data());
  }
}

BENCHMARK(BM_Butterworth)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);
BENCHMARK(BM_MovingAverage)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);
BENCHMARK(BM_RandomWalkKalman)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);

}  // namespace

BENCHMARK_MAIN();
