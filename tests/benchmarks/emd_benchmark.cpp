// EMD speed. Target: 10 fixed sifts of 1e6 white-noise samples in at most 1.5 s on one
// thread (libeemd 4.5 s, PyEMD 11.8 s on this machine class); and the pipeline's two-thread EMD
// at 1e6 and 8.64e6 samples (24 h at 100 Hz) when TBB is installed. Run with
//   emd_benchmark --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// and quote the median. Peak memory: run one size under /usr/bin/time -v, e.g.
//   /usr/bin/time -v emd_benchmark --benchmark_filter='EmdFixedSifts/1000000'
// and compare "Maximum resident set size" with (K + 4) N doubles (K IMFs, see emd.h).
#include <benchmark/benchmark.h>

#include <functional>
#ifdef FOGPIPE_BENCHMARK_WITH_TBB
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>
#endif

#include "algorithms/emd/emd.h"
#include "tests/algorithms/emd/test_signals.h"

namespace fogpipe::emd {
namespace {

void RunEmd(benchmark::State& state, const EmdOptions& options) {
  const int n = static_cast<int>(state.range(0));
  const Eigen::VectorXd x = testing::WhiteNoise(n, 42);
  int num_imfs = 0, sifts = 0;
  for (auto _ : state) {
    EmdResult r = Decompose(x, options);
    num_imfs = r.summary.num_imfs;
    sifts = r.summary.total_sifts;
    benchmark::DoNotOptimize(r.residue.data());
  }
  state.counters["imfs"] = num_imfs;
  state.counters["sifts"] = sifts;
  state.counters["ns_per_sample_sift"] = benchmark::Counter(
      static_cast<double>(n) * sifts,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_EmdFixedSifts(benchmark::State& state) { RunEmd(state, EmdOptions()); }
BENCHMARK(BM_EmdFixedSifts)->Arg(1 << 16)->Arg(1000000)->Unit(benchmark::kMillisecond);

void BM_EmdRilling(benchmark::State& state) {
  EmdOptions o;
  o.stop_rule = StopRule::kRilling;
  RunEmd(state, o);
}
BENCHMARK(BM_EmdRilling)->Arg(1 << 16)->Unit(benchmark::kMillisecond);

#ifdef FOGPIPE_BENCHMARK_WITH_TBB
// The pipeline's EMD (EmdOptions::for_each = a tbb::parallel_for, as pipeline/graph/campaign.cpp
// sets it): envelope splines solved at once and the envelope pass in parts, on 2 threads.
// Compare its real time with BM_EmdFixedSifts at the same size.
void TbbForEach(int n, const std::function<void(int)>& body) {
  tbb::parallel_for(0, n, [&](int i) { body(i); });
}

void BM_EmdFixedSiftsTwoThreads(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  EmdOptions o;
  o.for_each = TbbForEach;
  RunEmd(state, o);
}
BENCHMARK(BM_EmdFixedSifts)->Arg(8640000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmdFixedSiftsTwoThreads)
    ->Arg(1000000)
    ->Arg(8640000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
#endif

}  // namespace
}  // namespace fogpipe::emd

BENCHMARK_MAIN();
