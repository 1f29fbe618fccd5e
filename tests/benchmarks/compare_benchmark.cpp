// fogpipe::model::Compare on simulated navigation-grade recordings with a hidden temperature
// effect (so the base model is inconsistent and every trial fit runs). BM_Compare: one thread
// (Compare() runs the trials in order). BM_CompareTwoThreads: the pipeline's schedule (base
// model, then the IMF view and the trial fits through a ForEach, then the ranking) with a ForEach
// on two std::threads pulling indices from a shared counter, as oneTBB would.
#include <benchmark/benchmark.h>

#include <atomic>
#include <functional>
#include <thread>
#include <vector>

#include "algorithms/common/units.h"
#include "algorithms/model/compare.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"

namespace {

using namespace fogpipe;

struct Case {
  simulation::SimulatedRecording rec;
  model::CompareInput in;
};

Case Make(double hours, double fs) {
  auto o = simulation::NavigationGradeOptions(11);
  o.duration_s = hours * 3600.0;
  o.sample_rate_hz = fs;
  simulation::TemperatureEffect t;
  t.coefficient_rad_s_per_degC = units::DegPerHourToRadPerSecond(0.012);
  t.reference_degC = o.temperature->mean_degC;
  o.errors.temperature = t;
  Case c;
  c.rec = simulation::SimulateGyro(o);
  c.in.rate_rad_s = &c.rec.rate_rad_s;
  c.in.sample_rate_hz = fs;
  c.in.aux.push_back({"temperature", "degC", c.rec.temperature_degC});
  return c;
}

void BM_Compare(benchmark::State& state) {
  const Case c = Make(static_cast<double>(state.range(0)), static_cast<double>(state.range(1)));
  for (auto _ : state) {
    const auto r = model::Compare(c.in, model::DefaultTerms(), {});
    benchmark::DoNotOptimize(r.base.views.error);
  }
  state.counters["samples"] = static_cast<double>(c.rec.rate_rad_s.size());
}
BENCHMARK(BM_Compare)->Args({6, 10})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Compare)->Args({24, 100})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// A ForEach on `threads` std::threads pulling indices from a shared counter, as oneTBB would.
model::ForEach ThreadForEach(int threads) {
  return [threads](int n, const std::function<void(int)>& body) {
    std::atomic<int> next{0};
    auto work = [&] {
      for (int i = next++; i < n; i = next++) body(i);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
  };
}

void BM_CompareTwoThreads(benchmark::State& state) {
  const Case c = Make(static_cast<double>(state.range(0)), static_cast<double>(state.range(1)));
  for (auto _ : state) {
    const auto r = model::Compare(c.in, model::DefaultTerms(), {}, ThreadForEach(2));
    benchmark::DoNotOptimize(r.base.views.error);
  }
  state.counters["samples"] = static_cast<double>(c.rec.rate_rad_s.size());
}
BENCHMARK(BM_CompareTwoThreads)->Args({6, 10})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CompareTwoThreads)
    ->Args({24, 100})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
