// Tests algorithms/method/method.cpp on simulated recordings in the paper's setting
// (fogpipe::simulation::PaperOptions: 1 h at 1 Hz, navigation-grade N, B, K, Q; PaperDriftOptions:
// the same with Table 5's raw K/N and B/N; known truth),
// and on closed-form properties of the stages.
#include "algorithms/method/method.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "algorithms/allan/model_edf.h"
#include "algorithms/common/units.h"
#include "algorithms/method/tables.h"
#include "algorithms/method/white_noise.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/navigation_grade.h"
#include "algorithms/simulation/rate_profile.h"

namespace fogpipe::method {
namespace {

constexpr std::uint64_t kSeeds[] = {1, 2, 3};

Eigen::VectorXd PaperRecording(std::uint64_t seed) {
  const simulation::SimulatedRecording rec =
      simulation::SimulateGyro(simulation::PaperOptions(seed));
  EXPECT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
  return rec.rate_rad_s;
}

const MethodResult& PaperResult(std::uint64_t seed) {
  static std::map<std::uint64_t, MethodResult> cache;
  auto it = cache.find(seed);
  if (it == cache.end()) {
    it = cache.emplace(seed, RunMethod(PaperRecording(seed), 1.0, MethodOptions())).first;
  }
  return it->second;
}

// The paper's raw character (simulation::PaperDriftOptions: Table 5's K/N and B/N, rate random
// walk dominating beyond ~15 s) with the paper's fixed AR(6) for method 2; defaults otherwise.
const MethodResult& PaperDriftResult(std::uint64_t seed) {
  static std::map<std::uint64_t, MethodResult> cache;
  auto it = cache.find(seed);
  if (it == cache.end()) {
    const simulation::SimulatedRecording rec =
        simulation::SimulateGyro(simulation::PaperDriftOptions(seed));
    EXPECT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
    MethodOptions options;
    options.direct_ar_order = 6;  // the paper's direct AR(6) (docs/method.md, Table 3)
    it = cache.emplace(seed, RunMethod(rec.rate_rad_s, 1.0, options)).first;
  }
  return it->second;
}

void PrintTables(const char* profile, const MethodResult& (*result)(std::uint64_t)) {
  for (std::uint64_t seed : kSeeds) {
    const MethodResult& r = result(seed);
    ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
    std::printf("simulation::%s(seed %llu)\n%s%s\n", profile, static_cast<unsigned long long>(seed),
                FormatTable3(Table3(r)).c_str(), FormatTable5(Table5(r)).c_str());
  }
}

TEST(Method, PrintsTables3And5OnPaperLikeData) { PrintTables("PaperOptions", PaperResult); }

TEST(Method, PrintsTables3And5OnPaperDriftDataWithMethodTwoAr6) {
  PrintTables("PaperDriftOptions", PaperDriftResult);
}

// The shape of the paper's Table 3: every component's one-step fit is at or above the fit of
// the one AR model of the raw signal. It holds on PaperOptions (nearly white, raw fit ~1 %), not
// on PaperDriftOptions: there the raw AR(6) fits 22..57 % but imf1, EMD's highest-frequency mode
// of the white floor, fits 13..15 % (imf2 60..62 %, imf3 92..93 %, imf4 99.1..99.2 %). The paper's
// own Table 2 coefficients agree with us, not with its Table 3: their stationary one-step fits,
// 1 - sqrt(sigma_e^2 / var), are imf1 11.3 %, imf2 54.9 %, imf3 90.83 %, imf4 98.62 % (imf3 and
// imf4 equal the printed Table 3; imf1 and imf2 are printed as 85.47 and 87.65). So a raw record
// as coloured as the printed 74.66 % with a white floor cannot have imf1 fit above it.
// A free-run fit at or below -1000 % (a free response ten times the data's RMS) is printed as
// "diverged", never as a number; -999 % and the usual values are printed.
TEST(Method, Table3PrintsADivergedFreeRunAsDivergedNotAsANumber) {
  const std::vector<FitRow> rows = {{"imf1", 4, 80.0, 12.5},
                                    {"imf2", 8, 99.0, -999.0},
                                    {"imf3", 12, 99.9, -1.4e80},
                                    {"residue", 2, 99.9, std::nan("")}};
  const std::string table = FormatTable3(rows);
  EXPECT_NE(table.find("12.50"), std::string::npos) << table;
  EXPECT_NE(table.find("-999.00"), std::string::npos) << table;
  EXPECT_EQ(table.find("e+80"), std::string::npos) << table;
  EXPECT_EQ(table.find("nan"), std::string::npos) << table;
  std::size_t count = 0;
  for (std::size_t at = table.find("diverged"); at != std::string::npos;
       at = table.find("diverged", at + 1))
    ++count;
  EXPECT_EQ(count, 2u) << table;
}

// Components whose smoother output was replaced by the filter's are named once, under the table;
// without any, the table has no such line.
TEST(Method, Table3NamesTheComponentsWhoseSmootherKeptTheFiltersOutput) {
  std::vector<FitRow> rows = {
      {"imf1", 4, 80.0, 12.5}, {"imf2", 8, 99.0, 1.0}, {"residue", 2, 99.9, 3.0}};
  EXPECT_EQ(FormatTable3(rows).find("smoother:"), std::string::npos);
  rows[1].smoother_replaced = true;
  rows[2].smoother_replaced = true;
  const std::string table = FormatTable3(rows);
  EXPECT_NE(table.find("smoother: imf2, residue output their filter's estimate"), std::string::npos)
      << table;
}

TEST(Method, EveryComponentFitsAtLeastAsWellAsTheRawModel) {
  for (std::uint64_t seed : kSeeds) {
    const MethodResult& r = PaperResult(seed);
    ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
    const double raw = r.direct.fit.diagnostics.fit_one_step_percent;
    const int n = static_cast<int>(r.components.size()) - 1;
    ASSERT_GE(n, 5) << "EMD of 3600 samples of noise gives about log2(3600) - 1 IMFs";
    for (int k = 0; k <= n; ++k) {
      EXPECT_GE(r.components[k].fit.diagnostics.fit_one_step_percent, raw)
          << "seed " << seed << " " << ComponentName(k, n);
    }
  }
}

// Eq. 12 and the decomposition hold exactly: the stored pieces add up.
TEST(Method, ReconstructionIsTheSumOfTheFilteredComponentsInOrder) {
  const MethodResult& r = PaperResult(1);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(r.method1.size());
  for (const ComponentModel& c : r.components) sum += c.Output();
  EXPECT_EQ((sum - r.method1).cwiseAbs().maxCoeff(), 0.0);
  Eigen::VectorXd parts = r.decomposition.residue;
  for (const auto& imf : r.decomposition.imfs) parts += imf;
  // EMD's residue is x minus the IMFs: adding them back costs one rounding per IMF.
  const double scale = r.preprocessed.signal.cwiseAbs().maxCoeff();
  EXPECT_LE((parts - r.preprocessed.signal).cwiseAbs().maxCoeff(), 1e-13 * scale);
}

// The result must not depend on how the per-component loop is scheduled.
TEST(Method, ReverseOrderScheduleGivesIdenticalNumbers) {
  const Eigen::VectorXd x = PaperRecording(2);
  const MethodResult a = RunMethod(x, 1.0, MethodOptions());
  const MethodResult b = RunMethod(x, 1.0, MethodOptions(), [](int n, const auto& body) {
    for (int i = n - 1; i >= 0; --i) body(i);
  });
  EXPECT_TRUE(a.method1 == b.method1);
  EXPECT_TRUE(a.direct.Output() == b.direct.Output());
  EXPECT_EQ(a.method1_allan.allan.table.sigma, b.method1_allan.allan.table.sigma);
}

// A TaskGroup that runs every task on its own thread at once (real concurrency, an arbitrary
// interleaving), as the pipeline's tbb::task_group may.
// A thread per task. Tasks may start more tasks (TaskGroup's contract), so Run and Wait share a
// lock, and Wait joins until no task is left.
class ThreadTaskGroup : public TaskGroup {
 public:
  ~ThreadTaskGroup() override {
    try {
      Wait();
    } catch (...) {
    }
  }
  void Run(std::function<void()> task) override {
    std::lock_guard<std::mutex> lock(mutex_);
    threads_.emplace_back([this, task = std::move(task)] {
      try {
        task();
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!error_) error_ = std::current_exception();
      }
    });
  }
  void Wait() override {
    for (;;) {
      std::vector<std::thread> started;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        started.swap(threads_);
      }
      if (started.empty()) break;
      for (std::thread& t : started) t.join();
    }
    std::exception_ptr error;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      error.swap(error_);
    }
    if (error) std::rethrow_exception(error);
  }

 private:
  std::mutex mutex_;
  std::vector<std::thread> threads_;
  std::exception_ptr error_;  // the first task's exception, rethrown by Wait
};

void ThreadedForEach(int n, const std::function<void(int)>& body) {
  std::vector<std::thread> threads;
  for (int i = 0; i < n; ++i) threads.emplace_back([&body, i] { body(i); });
  for (std::thread& t : threads) t.join();
}

// Streaming the components through a store (one IMF in memory at a time per slot, the filtered
// ones released once added) must give run's numbers bit for bit, with or without the band limit
// and the smoother, one or several components in flight, serially or on threads.
TEST(Method, StreamingThroughAStoreGivesTheNumbersOfKeepingEveryComponent) {
  const Eigen::VectorXd x = PaperRecording(3);
  for (int variant = 0; variant < 4; ++variant) {
    MethodOptions options;
    if (variant == 1) options.band_limit.cutoff_ratio = 0.0;
    if (variant == 2) options.component.kalman.smooth = true;
    const MethodResult kept = RunMethod(x, 1.0, options);
    ASSERT_TRUE(HasResult(kept.summary.termination)) << kept.summary.message;
    const int num_imfs = kept.summary.num_imfs;
    ASSERT_GE(num_imfs, 5);
    MemoryComponentStore store;
    StreamOptions stream;
    stream.store = &store;
    stream.store_filtered = true;
    stream.components_in_flight = variant == 3 ? 1 : 3;
    if (variant >= 2) {
      stream.tasks = [] { return std::make_unique<ThreadTaskGroup>(); };
      stream.for_each = ThreadedForEach;
    }
    MethodResult streamed;
    DecomposeAndModel(x, 1.0, options, stream, &streamed);
    ASSERT_TRUE(HasResult(streamed.summary.termination)) << streamed.summary.message;
    EXPECT_TRUE(streamed.decomposition.imfs.empty());
    EXPECT_EQ(streamed.decomposition.residue.size(), 0);
    ASSERT_EQ(streamed.summary.num_imfs, num_imfs);
    EXPECT_TRUE(streamed.method1 == kept.method1) << "variant " << variant;
    EXPECT_TRUE(streamed.direct.Output() == kept.direct.Output());
    Eigen::VectorXd column;
    for (int k = 0; k <= num_imfs; ++k) {
      store.Get(ComponentStore::Kind::kComponent, k, &column);
      EXPECT_TRUE(column ==
                  (k < num_imfs ? kept.decomposition.imfs[k] : kept.decomposition.residue))
          << "component " << k;
      store.Get(ComponentStore::Kind::kFiltered, k, &column);
      EXPECT_TRUE(column == kept.components[k].Output()) << "filtered " << k;
      EXPECT_EQ(streamed.components[k].Output().size(), 0) << "released " << k;
      EXPECT_EQ(streamed.components[k].fit.model.phi, kept.components[k].fit.model.phi);
      EXPECT_EQ(streamed.components[k].kalman.r, kept.components[k].kalman.r);
      EXPECT_EQ(streamed.decomposition.imf_info.size(), kept.decomposition.imf_info.size());
      if (k < num_imfs) {
        EXPECT_EQ(streamed.decomposition.imf_info[k].mean_period_samples,
                  kept.decomposition.imf_info[k].mean_period_samples);
      }
    }
    for (std::size_t i = 0; i < kept.reference.size(); ++i)
      EXPECT_TRUE(streamed.reference[i].output.signal == kept.reference[i].output.signal);
  }
}

// A store that fails (a full scratch device, a read error) fails the decomposition with its
// exception, serially and on threads, after the components before it were stored; nothing hangs.
class FailingStore : public ComponentStore {
 public:
  /// Put of component `fail_put_at` throws, and so does Get of component `fail_get_at`.
  explicit FailingStore(int fail_put_at, int fail_get_at = -1)
      : fail_put_at_(fail_put_at), fail_get_at_(fail_get_at) {}
  void Put(Kind kind, int k, const Eigen::VectorXd& x) override {
    if (kind == Kind::kComponent && k == fail_put_at_)
      throw std::runtime_error("scratch device full");
    if (kind == Kind::kComponent) {
      std::lock_guard<std::mutex> lock(mutex_);
      stored_ = std::max(stored_, k + 1);
    }
    columns_.Put(kind, k, x);
  }
  void Get(Kind kind, int k, Eigen::VectorXd* x) const override {
    if (kind == Kind::kComponent && k == fail_get_at_)
      throw std::runtime_error("scratch read error");
    columns_.Get(kind, k, x);
  }
  bool Has(Kind kind, int k) const override { return columns_.Has(kind, k); }
  void Release(Kind kind, int k) override { columns_.Release(kind, k); }
  int stored() const { return stored_; }

 private:
  const int fail_put_at_;
  const int fail_get_at_;
  MemoryComponentStore columns_;
  std::mutex mutex_;
  int stored_ = 0;
};

// The error a streamed run on `store` ends with ("" when none), serially or on threads.
std::string StreamedRunError(ComponentStore* store, bool threaded) {
  StreamOptions stream;
  stream.store = store;
  if (threaded) {
    stream.tasks = [] { return std::make_unique<ThreadTaskGroup>(); };
    stream.for_each = ThreadedForEach;
  }
  MethodResult result;
  try {
    DecomposeAndModel(PaperRecording(3), 1.0, MethodOptions(), stream, &result);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(Method, AFailingStoreFailsTheDecompositionWithItsError) {
  for (const bool threaded : {false, true}) {
    FailingStore store(2);
    EXPECT_EQ(StreamedRunError(&store, threaded), "scratch device full") << "threaded " << threaded;
    EXPECT_EQ(store.stored(), 2) << "threaded " << threaded;
  }
}

// The fits read their component back from the store (the in-place AR fit): a read that fails
// fails the decomposition with its error, and the EMD stops within the components in flight.
TEST(Method, AStoreThatCannotReadAComponentBackFailsTheDecompositionWithItsError) {
  for (const bool threaded : {false, true}) {
    FailingStore store(-1, 1);
    EXPECT_EQ(StreamedRunError(&store, threaded), "scratch read error") << "threaded " << threaded;
    EXPECT_GE(store.stored(), 2) << "threaded " << threaded;
    EXPECT_LE(store.stored(), 1 + 2 + StreamOptions().components_in_flight)
        << "threaded " << threaded;
  }
}

// The streamed path keeps the staged one's decomposition: PreprocessAndDecompose (which the sweep
// starts from) and RunMethod see the same band-limited IMFs.
TEST(Method, RunMethodDecomposesAsPreprocessAndDecompose) {
  const Eigen::VectorXd x = PaperRecording(1);
  MethodResult staged;
  PreprocessAndDecompose(x, 1.0, MethodOptions(), &staged);
  const MethodResult& run = PaperResult(1);
  ASSERT_EQ(staged.decomposition.imfs.size(), run.decomposition.imfs.size());
  for (std::size_t k = 0; k < run.decomposition.imfs.size(); ++k)
    EXPECT_TRUE(staged.decomposition.imfs[k] == run.decomposition.imfs[k]) << k;
  EXPECT_TRUE(staged.decomposition.residue == run.decomposition.residue);
}

// The shape of the paper's Table 5 (method 1 lowers N and K by >= 10x against raw, and more
// than method 2). It does NOT hold, and is kept disabled as the record of that (the paper claims
// it; an honest negative beats a tuned positive). It runs on the faithful setting:
// PaperDriftOptions (Table 5's raw K/N and B/N, so raw K is measurable in 1 h) with the paper's
// AR(6) for method 2. Measured with the default noise rule of white_noise.h (seeds 1, 2, 3;
// raw -> method 1, method 2; PrintsTables3And5OnPaperLikeData prints them):
//   N deg/sqrt(h): 2.95e-3 -> 0, 0 | 6.09e-3 -> 0, 0 | 7.30e-3 -> 0, 0
//   K deg/h^1.5:   0.899 -> 1.07, 0.124 | 2.67 -> 2.12, 0.047 | 2.99 -> 2.44, 1.45
// Method 1 removes the white noise (the fast IMFs are judged pure noise and output their means,
// so N falls below what the fit resolves) but keeps the rate random walk, which its filters
// follow because it is signal to their AR models; method 2 (one AR(6) whose q the moment match
// makes small) lowers K further by narrowing the bandwidth, i.e. by over-smoothing
// (docs/method.md, "Cautions"), which a record with a moving true rate exposes
// (DefaultFiltersLowerTheErrorAgainstTheTrueRateAtEveryArOrder, and `fogpipe sweep`). On
// PaperOptions (navigation grade, nearly white; raw fit ~1 %) raw K is 0 in 1 h, so a 10x drop of
// K is not measurable there; method 1 lowers N there 70-140x (3.15e-3 -> 2.3e-5 on seed 1).
TEST(Method, DISABLED_MethodOneLowersNAndKTenfoldAndMoreThanMethodTwo) {
  for (std::uint64_t seed : kSeeds) {
    const std::vector<NoiseRow> t = Table5(PaperDriftResult(seed));
    EXPECT_LE(t[1].n_deg_sqrt_h, t[0].n_deg_sqrt_h / 10.0) << seed;
    EXPECT_LE(t[1].k_deg_h_sqrt_h, t[0].k_deg_h_sqrt_h / 10.0) << seed;
    EXPECT_LT(t[1].n_deg_sqrt_h, t[2].n_deg_sqrt_h) << seed;
    EXPECT_LT(t[1].k_deg_h_sqrt_h, t[2].k_deg_h_sqrt_h) << seed;
  }
}

// The default noise rule (method/white_noise.h, step 3): R_k is the white fraction of the
// component's AR innovation variance, so every component that is not all white noise gets q > 0
// (the filter keeps following its data), and one whose white share reaches its variance is judged
// pure noise: q = 0, and its output is its mean. Before fogpipe 0.2, R_k was the share itself and
// 64 of 64 components got q = 0 here (the filters ran their AR models free).
TEST(Method, EveryComponentGetsProcessNoiseUnlessItIsJudgedPureNoise) {
  int with_q = 0;
  for (std::uint64_t seed : kSeeds) {
    for (const MethodResult* r : {&PaperResult(seed), &PaperDriftResult(seed)}) {
      const int n = static_cast<int>(r->components.size()) - 1;
      const std::vector<double> variances = ComponentVariances(r->decomposition);
      for (int k = 0; k <= n; ++k) {
        const ComponentModel& c = r->components[k];
        const std::string name = "seed " + std::to_string(seed) + " " + ComponentName(k, n);
        if (c.white_noise_variance < variances[k]) {
          EXPECT_GT(c.kalman.q, 0.0) << name;
          EXPECT_LT(c.kalman.r, c.fit.model.innovation_variance) << name;
          ++with_q;
        } else {
          EXPECT_EQ(c.kalman.q, 0.0) << name;
          const Eigen::VectorXd& out = c.Output();
          EXPECT_EQ(out.maxCoeff(), out.minCoeff()) << name << ": a pure-noise output is constant";
          EXPECT_EQ(out[0], c.fit.model.mean) << name;
        }
      }
    }
  }
  // The drift profile's slow IMFs carry the rate random walk: not everything may be pure noise.
  EXPECT_GT(with_q, 0);
}

// A rate-table record with a known true rate: a step of 20 deg/h at 300 s, a ramp of
// 0.05 deg/h/s from 900 to 1200 s and a 10 deg/h sine at 5 mHz, under white noise
// N = 0.05 deg/sqrt(h) and a bias-instability floor B = 0.05 deg/h, 30 min at 10 Hz. Filtering
// is judged by the RMS error of the method-1 output against the true rate, where over-smoothing
// costs as much as noise. Raw RMS is ~9.5 deg/h (sigma = N sqrt(f_s)).
TEST(Method, DefaultFiltersLowerTheErrorAgainstTheTrueRateAtEveryArOrder) {
  for (std::uint64_t seed : {11, 12, 13}) {
    simulation::GyroSimulatorOptions o;
    o.sample_rate_hz = 10.0;
    o.duration_s = 1800.0;
    o.seed = seed;
    o.errors.n_rad_sqrt_s = units::DegPerSqrtHourToArw(0.05);
    o.errors.b_rad_s = units::DegPerHourToBias(0.05);
    std::string error;
    ASSERT_TRUE(simulation::ParseRateProfile("step:300:20,ramp:900:1200:0.05,sine:0.005:10",
                                             &o.input_rate, &error))
        << error;
    const simulation::SimulatedRecording rec = simulation::SimulateGyro(o);
    ASSERT_EQ(rec.summary.termination, Termination::kSuccess) << rec.summary.message;
    const double raw_rms = std::sqrt((rec.rate_rad_s - rec.true_rate_rad_s).squaredNorm() /
                                     static_cast<double>(rec.rate_rad_s.size()));
    for (int order : {2, 6, 12}) {
      MethodOptions options;
      options.component.ar.fixed_order = order;
      const MethodResult r = RunMethod(rec.rate_rad_s, o.sample_rate_hz, options);
      ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
      const Eigen::Index dropped = r.preprocessed.summary.dropped_samples;
      const Eigen::Index n = r.method1.size();
      const Eigen::ArrayXd err = r.method1.array() + r.preprocessed.mean_removed -
                                 rec.true_rate_rad_s.segment(dropped, n).array();
      const double rms = std::sqrt(err.square().mean());
      // At least halve the error: measured 0.22-0.23 x raw at every order on seed 4 with
      // `fogpipe sweep` (the rule of fogpipe < 0.2 made it 0.5-25 x raw, growing with the order).
      EXPECT_LT(rms, 0.5 * raw_rms) << "seed " << seed << " AR(" << order << ")";
      std::printf("seed %llu AR(%d): RMS error %.3f deg/h, raw %.3f deg/h\n",
                  static_cast<unsigned long long>(seed), order,
                  units::RadPerSecondToDegPerHour(rms), units::RadPerSecondToDegPerHour(raw_rms));
    }
  }
}

TEST(Method, ReportsTheStageThatFailed) {
  MethodResult r = RunMethod(Eigen::VectorXd::Constant(600, 1e-5), 1.0, MethodOptions());
  EXPECT_FALSE(HasResult(r.summary.termination));
  EXPECT_NE(r.summary.message.find("preprocessing"), std::string::npos) << r.summary.message;
  MethodOptions bad;
  bad.direct_ar_order = -1;
  r = RunMethod(PaperRecording(1), 1.0, bad);
  EXPECT_EQ(r.summary.termination, Termination::kInvalidOptions);
}

TEST(Method, RawTermsAreTheAllanCommandsTermsOfThePreprocessedSignal) {
  // `run`'s raw row and `fogpipe allan` share one code path (ComputeAllan, then
  // FitNoiseTermsAndModelEdf with default options, as allan_command.cpp calls them); the only
  // difference is the preprocessing that PreprocessingNote states. A start-up transient and gross
  // errors make that preprocessing matter here.
  Eigen::VectorXd x = PaperRecording(1);
  const double sd = std::sqrt((x.array() - x.mean()).square().mean());
  for (long k = 0; k < 120; ++k) x[k] += 20.0 * sd * std::exp(-k / 30.0);
  for (long k = 500; k < x.size(); k += 97) x[k] += 40.0 * sd;
  MethodOptions options;
  options.preprocess.drop_start_s = 120.0;
  const MethodResult r = RunMethod(x, 1.0, options);
  ASSERT_TRUE(HasResult(r.summary.termination)) << r.summary.message;
  EXPECT_EQ(r.preprocessed.summary.dropped_samples, 120);
  EXPECT_GT(r.preprocessed.summary.outliers, 0);

  const auto allan_command = [](const Eigen::VectorXd& signal) {
    allan::AllanResult a = allan::ComputeAllan(signal, 1.0, allan::AllanOptions{});
    return allan::FitNoiseTermsAndModelEdf(allan::NoiseFitOptions{},
                                           allan::AllanOptions{}.confidence, &a.table);
  };
  const allan::NoiseFitResult same = allan_command(r.preprocessed.signal);
  const allan::NoiseTerms& a = r.raw_allan.noise.terms;
  const allan::NoiseTerms& b = same.terms;
  EXPECT_EQ(a.q_rad, b.q_rad);
  EXPECT_EQ(a.n_rad_sqrt_s, b.n_rad_sqrt_s);
  EXPECT_EQ(a.b_rad_s, b.b_rad_s);
  EXPECT_EQ(a.k_rad_s_sqrt_s, b.k_rad_s_sqrt_s);
  EXPECT_EQ(a.r_rad_s2, b.r_rad_s2);
  for (int j = 0; j < allan::kNoiseTermCount; ++j) {
    EXPECT_EQ(r.raw_allan.noise.assessment[j].reliable, same.assessment[j].reliable);
    EXPECT_EQ(r.raw_allan.noise.assessment[j].reason, same.assessment[j].reason);
  }
  // On the recording as stored the terms differ: the preprocessing is the difference.
  const allan::NoiseFitResult stored = allan_command(x);
  EXPECT_NE(stored.terms.n_rad_sqrt_s, a.n_rad_sqrt_s);
}

}  // namespace
}  // namespace fogpipe::method
