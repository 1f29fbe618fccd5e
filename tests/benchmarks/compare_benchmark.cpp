// fogpipe::model::Compare on simulated navigation-grade recordings with a hidden temperature
// effect (so the base model is inconsistent and every trial fit runs). Single thread.
#include <benchmark/benchmark.h>

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

}  // namespace

BENCHMARK_MAIN();
