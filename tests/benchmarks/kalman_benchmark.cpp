// Steady-state AR Kalman filtering, ns per sample, for orders 1..8 and 20 on 1e7 samples.
// Run: build/tests/benchmarks/kalman_benchmark --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true
// The filter is entered through the public FilterAr() with its default steady-state start (no
// time-varying phase); the DARE solve is included and negligible. BM_PaperStart measures the
// paper's start on a slowly converging model (time-varying phase up to the step cap), and
// BM_SideBySide the sweep's batch of q/R settings (AddSteadyStateFilters), per filter and sample.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "algorithms/kalman/ar_kalman.h"
#include "algorithms/kalman/riccati.h"
#include "algorithms/kalman/steady_state_filter.h"

namespace {

constexpr long long kSamples = 10'000'000;

// A stable AR(p): poles at radius 0.9 spread in angle, expanded into recursion coefficients.
Eigen::VectorXd StablePhi(int p) {
  Eigen::VectorXd poly = Eigen::VectorXd::Zero(p + 1);  // 1 + c1 B + ... (real poles and pairs)
  poly[0] = 1.0;
  int used = 0;
  auto multiply = [&](double c1, double c2) {
    for (int i = p; i >= 1; --i) {
      poly[i] += c1 * poly[i - 1] + (i >= 2 ? c2 * poly[i - 2] : 0.0);
    }
  };
  for (int pair = 0; used + 2 <= p; ++pair, used += 2) {
    const double angle = 0.3 + 0.4 * pair;
    multiply(-2.0 * 0.9 * std::cos(angle), 0.81);
  }
  if (used < p) multiply(-0.9, 0.0);
  return -poly.tail(p);
}

const Eigen::VectorXd& Signal() {
  static const Eigen::VectorXd z = [] {
    std::mt19937_64 engine(1);
    Eigen::VectorXd v(kSamples);
    double prev = 0.0;
    for (long long k = 0; k < kSamples; ++k) {
      const double u = static_cast<double>(engine() >> 11) * 0x1.0p-53 - 0.5;
      prev = 0.99 * prev + u;
      v[k] = prev + u;
    }
    return v;
  }();
  return z;
}

// ns per sample from CPU time (the machine is shared; wall time also counts other processes).
benchmark::Counter NsPerSample(const benchmark::State& state) {
  return benchmark::Counter(static_cast<double>(kSamples) * state.iterations() * 1e-9,
                            benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The constant-gain loop alone, output buffer allocated once: the per-sample cost of filtering.
void BM_SteadyStateLoop(benchmark::State& state) {
  const int p = static_cast<int>(state.range(0));
  const Eigen::VectorXd phi = StablePhi(p);
  const Eigen::VectorXd& z = Signal();
  const fogpipe::kalman::DareSolution dare = fogpipe::kalman::SolveDare(phi, 0.01, 0.1);
  Eigen::VectorXd out(kSamples);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(p);
  for (auto _ : state) {
    fogpipe::kalman::SteadyStateFilter(z.data(), kSamples, 0.0, phi, dare.gain, x0, out.data(),
                                       nullptr);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_sample"] = NsPerSample(state);
}
BENCHMARK(BM_SteadyStateLoop)->DenseRange(1, 8)->Arg(20)->Unit(benchmark::kMillisecond);

// The public entry point end to end: validation and variance pass, DARE, time-varying start,
// switch. range(1) == 1: the output vector is reused across calls (FilterAr's `reuse`); 0: a fresh
// 8e7-byte output per call, whose page faults are then part of the cost.
void BM_SteadyStateFilter(benchmark::State& state) {
  const int p = static_cast<int>(state.range(0));
  const bool reuse = state.range(1) == 1;
  const Eigen::VectorXd phi = StablePhi(p);
  const Eigen::VectorXd& z = Signal();
  fogpipe::kalman::ArKalmanOptions options;
  options.q = 0.01;
  options.r = 0.1;
  Eigen::VectorXd storage;
  for (auto _ : state) {
    auto result =
        fogpipe::kalman::FilterAr(z, phi, -1.0, -1.0, options, reuse ? &storage : nullptr);
    benchmark::DoNotOptimize(result.filtered.data());
    if (result.summary.switched_at_sample < 0) state.SkipWithError("no steady-state switch");
    if (reuse) storage.swap(result.filtered);
  }
  state.counters["ns_per_sample"] = NsPerSample(state);
}
BENCHMARK(BM_SteadyStateFilter)
    ->ArgsProduct({{1, 2, 3, 4, 5, 6, 20}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

// The paper's start (P0 = var(z) I) on a lightly damped AR(2) (poles at radius 0.9999) with
// q/R = 1e-8: the gain needs ~1e5 time-varying O(p^2) steps to converge, so the filter runs up
// to max_time_varying_steps (range(0); 0 = no cap) and then switches.
void BM_PaperStart(benchmark::State& state) {
  const double radius = 0.9999;
  Eigen::VectorXd phi(2);
  phi << 2.0 * radius * std::cos(0.01), -radius * radius;
  const Eigen::VectorXd& z = Signal();
  fogpipe::kalman::ArKalmanOptions options;
  options.q = 1e-8;
  options.r = 1.0;
  options.initial_covariance = fogpipe::kalman::InitialCovariance::kSampleVariance;
  options.max_time_varying_steps = state.range(0);
  Eigen::VectorXd storage;
  for (auto _ : state) {
    auto result = fogpipe::kalman::FilterAr(z, phi, -1.0, -1.0, options, &storage);
    benchmark::DoNotOptimize(result.filtered.data());
    state.counters["time_varying_steps"] = static_cast<double>(
        result.summary.switched_at_sample < 0 ? kSamples : result.summary.switched_at_sample);
    storage.swap(result.filtered);
  }
  state.counters["ns_per_sample"] = NsPerSample(state);
}
BENCHMARK(BM_PaperStart)->Arg(1 << 16)->Arg(0)->Unit(benchmark::kMillisecond);

// The sweep's batch: 10 steady-state filters of one AR(p) model (a 3 x 3 q/R grid + the default
// rule) side by side over the same z, each adding into its own sum; ns per filter and sample.
// Second argument 1: the sums interleaved sample by sample in ranges of 2048 samples, as the
// sweep (method/sweep_evaluate.cpp) adds them.
void BM_SideBySide(benchmark::State& state) {
  const int p = static_cast<int>(state.range(0));
  const bool interleaved = state.range(1) != 0;
  const Eigen::VectorXd phi = StablePhi(p);
  const Eigen::VectorXd& z = Signal();
  const int filters = 10;
  constexpr long long kRange = 2048;
  std::vector<fogpipe::kalman::DareSolution> dares;
  for (int i = 0; i < filters; ++i) {
    dares.push_back(fogpipe::kalman::SolveDare(phi, 0.001 * (i + 1), 0.1));
  }
  std::vector<Eigen::VectorXd> sums(filters, Eigen::VectorXd::Zero(kSamples));
  std::vector<double> range_sums(static_cast<std::size_t>(kRange * filters), 0.0);
  // Each filter's loop state (from X = 0), carried from one iteration to the next.
  std::vector<std::vector<double>> partial(filters, std::vector<double>(p, 0.0));
  std::vector<fogpipe::kalman::SteadyStateLane> lanes;
  for (int i = 0; i < filters; ++i) {
    lanes.push_back({&dares[i].gain, 0.0, interleaved ? range_sums.data() + i : sums[i].data(),
                     partial[i].data(), nullptr, interleaved ? filters : 1});
  }
  for (auto _ : state) {
    if (!interleaved) {
      fogpipe::kalman::AddSteadyStateFilters(z.data(), kSamples, phi, lanes);
    } else {
      for (long long k = 0; k < kSamples; k += kRange) {
        fogpipe::kalman::AddSteadyStateFilters(z.data() + k, std::min(kRange, kSamples - k), phi,
                                               lanes);
      }
    }
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_filter_sample"] =
      benchmark::Counter(static_cast<double>(kSamples) * filters * state.iterations() * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SideBySide)->ArgsProduct({{2, 4, 8, 12}, {0, 1}})->Unit(benchmark::kMillisecond);

void BM_SteadyStateSmoother(benchmark::State& state) {
  const int p = static_cast<int>(state.range(0));
  const Eigen::VectorXd phi = StablePhi(p);
  const Eigen::VectorXd& z = Signal();
  fogpipe::kalman::ArKalmanOptions options;
  options.q = 0.01;
  options.r = 0.1;
  options.smooth = true;
  for (auto _ : state) {
    auto result = fogpipe::kalman::FilterAr(z, phi, -1.0, -1.0, options);
    benchmark::DoNotOptimize(result.smoothed.data());
  }
  state.counters["ns_per_sample"] = NsPerSample(state);
}
BENCHMARK(BM_SteadyStateSmoother)->Arg(2)->Arg(4)->Arg(6)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
