// The model history of `fogpipe compare -o RESULTS` (pipeline/io/model_history.h): a comparison
// of a simulated recording is appended and read back through the HDF5 layer; every view scalar of
// the targeted tests (Gauss-Markov bump, bias-step and warm-up scans) and the frequency view's
// Welch dof must come back bit for bit with its units (schemas/model-history.md).
#include "pipeline/io/model_history.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "algorithms/common/units.h"
#include "algorithms/model/compare.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"
#include "pipeline/hdf5/file.h"
#include "pipeline/hdf5/group.h"

namespace fogpipe {
namespace {

namespace fs = std::filesystem;

struct Scalar {
  std::string path;
  double value;
  std::string units;
};

TEST(ModelHistory, StoresEveryTargetedTestFieldWithItsUnits) {
  // 2 h at 10 Hz, navigation grade, with a bias step: the time view's scans find it, so the
  // step fields are far from their zero defaults.
  auto o = simulation::NavigationGradeOptions(7);
  o.duration_s = 7200.0;
  simulation::BiasStep step;
  step.time_s = 3000.0;
  step.size_rad_s = units::DegPerHourToRadPerSecond(0.05);
  o.errors.bias_steps.push_back(step);
  const simulation::SimulatedRecording rec = simulation::SimulateGyro(o);
  model::CompareInput in;
  in.rate_rad_s = &rec.rate_rad_s;
  in.sample_rate_hz = o.sample_rate_hz;
  in.aux.push_back({"temperature", "degC", rec.temperature_degC});
  const model::CompareResult r = model::Compare(in, model::DefaultTerms(), {});
  ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
  const model::Views& v = r.base.views;
  ASSERT_GT(v.time.step_time_s, 0.0);  // the scan ran
  ASSERT_GT(v.frequency.dof, 2.0);     // Welch, several segments

  const fs::path dir = fs::temp_directory_path() / ("fogpipe_history_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string results = (dir / "results.h5").string();
  EXPECT_EQ(io::AppendHistory(results, "rec.h5", "0", r), 0);
  EXPECT_EQ(io::AppendHistory(results, "rec.h5", "0", r), 1);  // appends, keeps step 0

  const std::vector<Scalar> scalars = {
      {"allan/gm_z", v.allan.gm_z, "1"},
      {"allan/gm_critical", v.allan.gm_critical, "1"},
      {"allan/gm_correlation_time_s", v.allan.gm_correlation_time_s, "s"},
      {"allan/gm_sigma_rad_s", v.allan.gm_sigma_rad_s, "rad/s"},
      {"time/step_z", v.time.step_z, "1"},
      {"time/step_critical", v.time.step_critical, "1"},
      {"time/step_time_s", v.time.step_time_s, "s"},
      {"time/step_size_rad_s", v.time.step_size_rad_s, "rad/s"},
      {"time/warmup_z", v.time.warmup_z, "1"},
      {"time/warmup_critical", v.time.warmup_critical, "1"},
      {"time/warmup_time_constant_s", v.time.warmup_time_constant_s, "s"},
      {"time/warmup_amplitude_rad_s", v.time.warmup_amplitude_rad_s, "rad/s"},
  };
  {
    const hdf5::File f = hdf5::File::OpenReadOnly(results);
    const hdf5::Group root = f.Root();
    for (const char* step_name : {"compare/step_000", "compare/step_001"}) {
      const hdf5::Group s = root.OpenGroup(step_name);
      for (const Scalar& x : scalars) {
        const hdf5::Dataset d = s.OpenDataset(x.path);
        EXPECT_EQ(d.ReadDoubles(), std::vector<double>{x.value}) << step_name << "/" << x.path;
        EXPECT_EQ(d.ReadStringAttribute("units"), x.units) << x.path;
      }
      const hdf5::Group freq = s.OpenGroup("frequency");
      EXPECT_EQ(freq.ReadDoubleAttribute("dof"), v.frequency.dof);
      EXPECT_EQ(freq.ReadDoubleAttribute("scale"), v.frequency.scale);
      EXPECT_EQ(freq.OpenDataset("psd").ReadDoubles(), v.frequency.psd);
    }
  }
  const auto history = io::ReadHistory(results);
  ASSERT_EQ(history.size(), 2u);
  EXPECT_EQ(history[1].error, v.error);
  std::error_code ec;
  fs::remove_all(dir, ec);
}

TEST(ModelHistory, TheComparisonIsTheSameOnAnyNumberOfThreads) {
  // model::Compare runs the trials and the IMF view through a ForEach; each task writes only its
  // own slot, so a 2-thread schedule (tasks pulled from a shared counter) must give the same JSON.
  auto o = simulation::NavigationGradeOptions(9);
  o.duration_s = 7200.0;
  simulation::TemperatureEffect t;
  t.coefficient_rad_s_per_degC = units::DegPerHourToRadPerSecond(0.03);
  t.reference_degC = o.temperature->mean_degC;
  o.errors.temperature = t;
  const simulation::SimulatedRecording rec = simulation::SimulateGyro(o);
  model::CompareInput in;
  in.rate_rad_s = &rec.rate_rad_s;
  in.sample_rate_hz = o.sample_rate_hz;
  in.aux.push_back({"temperature", "degC", rec.temperature_degC});
  const model::ForEach two_threads = [](int n, const std::function<void(int)>& body) {
    std::atomic<int> next{0};
    auto work = [&] {
      for (int i = next++; i < n; i = next++) body(i);
    };
    std::thread other(work);
    work();
    other.join();
  };
  const model::CompareResult serial = model::Compare(in, model::DefaultTerms(), {});
  const model::CompareResult parallel = model::Compare(in, model::DefaultTerms(), {}, two_threads);
  ASSERT_FALSE(serial.suggestions.empty());  // trials ran
  EXPECT_EQ(io::CompareJson(serial).dump(), io::CompareJson(parallel).dump());
}

}  // namespace
}  // namespace fogpipe

namespace fogpipe {
namespace {

// A bias_levels component goes to the model file with its step times and comes back with them
// (schemas/model-file.md); its sizes are the coefficients, in the same order.
TEST(ModelFile, KeepsTheStepTimesOfBiasLevels) {
  model::Evaluation e;
  e.terms = {model::Term::kWhite, model::Term::kBiasLevels};
  model::DeterministicComponent levels;
  levels.term = model::Term::kBiasLevels;
  levels.step_times_s = {1200.5, 7300.25, 15000.0};
  levels.coefficients = {1e-7, -2e-7, 3e-7};
  levels.coefficients_se = {1e-8, 1e-8, 1e-8};
  levels.step_times_se_s = {5.0, 6.0, 7.0};
  e.deterministic.model.components.push_back(levels);
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("levels_model_" + std::to_string(getpid()) + ".json"))
                               .string();
  io::WriteModelFile(path, e);
  const io::ModelFile m = io::ReadModelFile(path);
  std::filesystem::remove(path);
  ASSERT_EQ(m.deterministic.components.size(), 1u);
  EXPECT_EQ(m.deterministic.components[0].step_times_s, levels.step_times_s);
  EXPECT_EQ(m.deterministic.components[0].coefficients, levels.coefficients);
}

}  // namespace
}  // namespace fogpipe
