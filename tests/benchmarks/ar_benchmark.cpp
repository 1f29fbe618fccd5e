// AR benchmarks. Run with repetitions and report medians, e.g.
//   build/tests/benchmarks/ar_benchmark --benchmark_repetitions=7
//   --benchmark_report_aggregates_only=true
// Target: AR orders 1-20 with BIC on 1e6 samples in at most 50 ms, one thread (a small share of
// the per-component modelling of a long record).
#include <benchmark/benchmark.h>

#include "algorithms/ar/burg.h"
#include "algorithms/ar/diagnostics.h"
#include "algorithms/ar/fit_ar.h"
#include "tests/algorithms/ar/ar_test_support.h"

namespace fogpipe::ar {
namespace {

const Eigen::VectorXd& Imf6Record(Eigen::Index n) {
  static Eigen::VectorXd x;
  if (x.size() != n) x = testing::SimulateAr(testing::PaperImf6Phi(), 1e-3, n, 7);
  return x;
}

// The speed target: mean removal + Burg orders 1..20 + BIC + selected model (roots, std errors).
void BM_FitArBurgBicOrders1To20(benchmark::State& state) {
  const Eigen::VectorXd& x = Imf6Record(state.range(0));
  ArOptions options;
  options.compute_diagnostics = false;
  for (auto _ : state) {
    ArFit fit = FitAr(x, options);
    benchmark::DoNotOptimize(fit.model.phi.data());
  }
  state.SetItemsProcessed(state.iterations() * x.size());
}
BENCHMARK(BM_FitArBurgBicOrders1To20)->Arg(1000000)->Arg(10000000)->Unit(benchmark::kMillisecond);

// The Burg recursion alone (no copy of the input, no model post-processing).
void BM_BurgAllOrders20(benchmark::State& state) {
  const Eigen::VectorXd& x = Imf6Record(state.range(0));
  for (auto _ : state) {
    OrderSequence seq = BurgAllOrders(x, 20);
    benchmark::DoNotOptimize(seq.innovation_variance.data());
  }
}
BENCHMARK(BM_BurgAllOrders20)->Arg(1000000)->Unit(benchmark::kMillisecond);

// Vos (2013) autocorrelation form: one pass for c(0..21) plus O(P^4) small work. Not used by
// FitAr (it loses ~8 digits on imf6, see burg_test.cpp); measured for the comparison.
void BM_BurgFromAutocorrelation20(benchmark::State& state) {
  const Eigen::VectorXd& x = Imf6Record(state.range(0));
  for (auto _ : state) {
    OrderSequence seq = BurgAllOrdersFromAutocorrelation(x, 20);
    benchmark::DoNotOptimize(seq.innovation_variance.data());
  }
}
BENCHMARK(BM_BurgFromAutocorrelation20)->Arg(1000000)->Unit(benchmark::kMillisecond);

// Diagnostics are separate passes: one-step residuals, free-run simulation, Ljung-Box lags 10/20.
void BM_DiagnosticsAr4(benchmark::State& state) {
  const Eigen::VectorXd& x = Imf6Record(state.range(0));
  const ArModel model = MakeArModel(testing::PaperImf6Phi(), 1e-6, 0.0, x.size());
  for (auto _ : state) {
    ArDiagnostics d = ComputeDiagnostics(x, model);
    benchmark::DoNotOptimize(d.ljung_box_p20);
  }
}
BENCHMARK(BM_DiagnosticsAr4)->Arg(1000000)->Unit(benchmark::kMillisecond);

// The other estimators, orders 1..20 with BIC (ML: Burg's BIC, then ML at the selected order).
void BM_FitArEstimator(benchmark::State& state) {
  const Eigen::VectorXd& x = Imf6Record(1000000);
  ArOptions options;
  options.compute_diagnostics = false;
  options.estimator = static_cast<Estimator>(state.range(0));
  state.SetLabel(ToString(options.estimator));
  for (auto _ : state) {
    ArFit fit = FitAr(x, options);
    benchmark::DoNotOptimize(fit.model.phi.data());
  }
}
BENCHMARK(BM_FitArEstimator)
    ->Arg(static_cast<int>(Estimator::kLeastSquaresQr))
    ->Arg(static_cast<int>(Estimator::kYuleWalker))
    ->Arg(static_cast<int>(Estimator::kMaximumLikelihood))
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace fogpipe::ar

BENCHMARK_MAIN();
