#include "algorithms/method/sweep_evaluate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "algorithms/ar/ar_model.h"
#include "algorithms/ar/burg.h"
#include "algorithms/ar/diagnostics.h"
#include "algorithms/ar/order_selection.h"
#include "algorithms/common/idle_pool.h"
#include "algorithms/common/units.h"
#include "algorithms/kalman/ar_filter_bank.h"
#include "algorithms/method/component.h"
#include "algorithms/method/white_noise.h"

namespace fogpipe::method {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The sweep's cap on each filter's time-varying phase (kalman::ArKalmanOptions::
// max_time_varying_steps; `run` keeps its default). The paper's diffuse start locks on within a
// few hundred samples; after 4096 steps the switch to G_inf changes the output by an amount
// driven by the recorded gain distance and forgotten at the closed-loop radius^k (tested in
// ar_kalman_test). 65536 steps would triple the sweep's cost on 1 h at 100 Hz.
constexpr long long kSweepTimeVaryingSteps = 4096;
// Samples of every setting's method-1 sum filled by all components before the next range: 10
// settings x 2048 x 8 bytes = 160 kB stay in the L2 cache while the components add to them.
constexpr Eigen::Index kSumRange = 2048;

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Signal-length buffers (common/idle_pool.h): the settings' method-1 sums and the phases of
/// their Allan tables.
class BufferPool {
 public:
  /// A buffer of n doubles (contents unspecified): an idle one of that size, else a new one.
  Eigen::VectorXd Take(Eigen::Index n) {
    Eigen::VectorXd v = idle_.Take([n](const Eigen::VectorXd& b) { return b.size() == n; });
    if (v.size() != n) v.resize(n);
    return v;
  }
  void Give(Eigen::VectorXd* v) {
    if (v->size() > 0) idle_.Give(v);
  }
  void Release() { idle_.Release(); }

 private:
  IdlePool<Eigen::VectorXd> idle_;
};

/// The models of one component for every order 1..max_order from one Burg recursion.
struct ComponentModels {
  const Eigen::VectorXd* signal = nullptr;
  bool constant = false;            ///< passed through unfiltered (see ModelComponent)
  double white_noise = 0.0;         ///< white-noise share (white_noise.h), x^2
  double variance = 0.0;            ///< the component's variance, x^2
  double filter_variance = 0.0;     ///< its sample variance as the Kalman filter computes it, x^2
  bool filter_variance_ok = false;  ///< (kalman::FilterInputVariance)
  std::vector<ar::ArModel> models;  ///< models[p - 1]; fewer when the recursion stopped early
  std::vector<double> fit_one_step, fit_simulation;  ///< per order, % (NaN: no setting uses it)
  std::vector<double> centered_energy;  ///< per used order: ar::CenteredTailEnergy, x^2
  std::vector<bool> used;               ///< per order: some setting uses it (fits computed)
};

/// The order used for a setting's order p: the highest order up to p, and up to the order the
/// recursion reached (the prediction error vanished there: the component is exactly predictable),
/// whose model is stationary as stored (ar::SelectStationaryOrder, as ar::FitAr applies it for
/// `run`). 0 for a component without models.
int UsedOrder(const ComponentModels& c, int p) {
  const int reached = static_cast<int>(c.models.size());
  if (reached == 0) return 0;
  return ar::SelectStationaryOrder(Eigen::VectorXd::Zero(reached), std::min(p, reached),
                                   [&c](int q) { return c.models[q - 1].stationary; });
}

/// The next stationary order below `used` that a broken-down filter falls back to, 0 if none.
int LowerOrder(const ComponentModels& c, int used) {
  const int lower = used > 1 ? UsedOrder(c, used - 1) : 0;
  return lower >= 1 && lower < used ? lower : 0;
}

/// The Kalman options of one setting's filter on component c with `model` (one of c's models).
/// Grid settings: q referred to sigma_e^2, R to the white share (sweep_grid.h); the default rule:
/// exactly ModelComponent()'s (ComponentFilterOptions).
kalman::ArKalmanOptions SettingFilterOptions(const ComponentModels& c, const ar::ArModel& model,
                                             const SweepSetting& setting,
                                             const SweepOptions& options) {
  ComponentOptions component = options.method.component;
  component.kalman.q_scale = setting.default_rule ? 1.0 : setting.q_scale;
  component.kalman.r_scale = setting.default_rule ? 1.0 : setting.r_scale;
  component.kalman.max_time_varying_steps = kSweepTimeVaryingSteps;
  if (setting.default_rule) {
    double r = 0.0;
    kalman::ArKalmanOptions o =
        ComponentFilterOptions(component, c.white_noise, c.variance, model, &r);
    if (o.r < 0.0) o.r = r;
    return o;
  }
  kalman::ArKalmanOptions o = component.kalman;
  o.mean = model.mean;
  o.q = model.innovation_variance;
  if (o.r < 0.0) o.r = c.white_noise;
  return o;
}

/// Table 3's fits (one-step, simulation; %) of component c's order-p model: the cached values for
/// the grid's orders, else computed here (a lower order reached by a fallback).
std::pair<double, double> FitsOfOrder(const ComponentModels& c, int p) {
  if (c.used[p - 1]) return {c.fit_one_step[p - 1], c.fit_simulation[p - 1]};
  const Eigen::VectorXd& x = *c.signal;
  const double energy = ar::CenteredTailEnergy(x, p);
  return {ar::OneStepFitPercent(x, c.models[p - 1], energy),
          ar::SimulationFitPercents({{x.data(), x.size(), &c.models[p - 1], energy}}).front()};
}

/// Scores `signal` (a setting's method 1 or a reference filter's output, preprocessed like
/// `pre`) as every sweep point is scored: its Allan table and noise terms, and the RMS of
/// (signal + removed mean) - true rate when there is a truth. False, with the point's termination
/// and message, when the Allan table has no result.
bool ScoreSignal(const Eigen::VectorXd& signal, double sample_rate_hz, const SweepOptions& options,
                 const Preprocessed& pre, const Eigen::VectorXd* truth, BufferPool* buffers,
                 SweepPoint* point) {
  Eigen::VectorXd phase = buffers->Take(signal.size() + 1);
  point->allan.allan = allan::ComputeAllan(signal, sample_rate_hz, options.method.allan, &phase);
  buffers->Give(&phase);
  if (!HasResult(point->allan.allan.summary.termination)) {
    point->termination = point->allan.allan.summary.termination;
    point->message = "Allan variance: " + point->allan.allan.summary.message;
    return false;
  }
  point->allan.noise = allan::FitNoiseTerms(point->allan.allan.table, options.method.noise_fit);
  point->rms_error = kNaN;
  if (truth != nullptr) {
    const Eigen::Index n = signal.size();
    point->rms_error = std::sqrt(((signal.array() + pre.mean_removed) -
                                  truth->segment(pre.summary.dropped_samples, n).array())
                                     .square()
                                     .mean());
  }
  return true;
}

/// The reference filters on the sweep's preprocessed signal, each scored like a grid setting.
void EvaluateReferences(double sample_rate_hz, const SweepOptions& options,
                        const Eigen::VectorXd* truth, const ForEach& for_each, BufferPool* buffers,
                        SweepResult* out) {
  const auto start = std::chrono::steady_clock::now();
  RunReferenceFilters(sample_rate_hz, options.method, for_each, &out->base);
  const int count = static_cast<int>(out->base.reference.size());
  const double filter_seconds = SecondsSince(start) / std::max(1, count);
  out->reference.assign(count, SweepReference());
  for_each(count, [&](int i) {
    const auto allan_start = std::chrono::steady_clock::now();
    const filters::ReferenceOutput& o = out->base.reference[i].output;
    SweepReference& r = out->reference[i];
    r.name = o.name;
    r.parameter_name = o.parameter_name;
    r.parameter_units = o.parameter_units;
    r.parameter = o.parameter;
    r.point.termination = o.termination;
    r.point.message = o.message;
    r.point.rms_error = kNaN;
    if (!HasResult(o.termination)) return;
    if (!ScoreSignal(o.signal, sample_rate_hz, options, out->base.preprocessed, truth, buffers,
                     &r.point))
      return;
    r.point.seconds = filter_seconds + SecondsSince(allan_start);
  });
  // The signals are not kept (the sweep stores scores only).
  for (ReferenceEvaluation& e : out->base.reference) e.output.signal = Eigen::VectorXd();
}

/// Fails `summary` when the options or the truth's length do not fit the signal `x`.
bool CheckInputs(const Eigen::VectorXd& x, const SweepOptions& options,
                 const Eigen::VectorXd* truth, SweepSummary* summary) {
  std::string error;
  if (!options.IsValid(&error)) {
    summary->termination = Termination::kInvalidOptions;
    summary->message = error;
    return false;
  }
  if (truth != nullptr && truth->size() != x.size()) {
    summary->termination = Termination::kInvalidOptions;
    summary->message = "the true rate has " + std::to_string(truth->size()) +
                       " samples, the signal " + std::to_string(x.size());
    return false;
  }
  return true;
}

/// The components (IMFs, then the residue) of the decomposition in `base`, each with its white
/// share and variance: R per component by the same rule as ModelComponents() (white_noise.h).
std::vector<ComponentModels> SetUpComponents(const MethodResult& base) {
  const emd::EmdResult& e = base.decomposition;
  const Eigen::VectorXd& signal = base.preprocessed.signal;
  const int num_imfs = static_cast<int>(e.imfs.size());
  const std::vector<double> variances = ComponentVariances(e);
  const std::vector<double> r = ShareWhiteNoise(EstimateWhiteNoiseLevels(signal),
                                                ComponentPeriods(e, signal.size()), variances);
  std::vector<ComponentModels> components(num_imfs + 1);
  for (int k = 0; k <= num_imfs; ++k) {
    ComponentModels& m = components[k];
    m.signal = k < num_imfs ? &e.imfs[k] : &e.residue;
    m.white_noise = r[k];
    m.variance = variances[k];
    m.constant = IsConstantComponent(*m.signal);
  }
  return components;
}

/// One Burg recursion up to the grid's largest order gives m's models of every order; then the
/// one-step fit % of the orders some setting uses (min(p, orders reached) for every p of the
/// grid). The simulation fits follow across components (FitSimulations).
void FitAllOrders(const SweepGrid& grid, IdlePool<ar::BurgWork>* burg_work, ComponentModels* m) {
  if (m->constant) return;
  const Eigen::VectorXd& c = *m->signal;
  m->filter_variance_ok = kalman::FilterInputVariance(c, &m->filter_variance);
  const double mean = c.mean();
  ar::BurgWork work = burg_work->Take();
  const ar::OrderSequence sequence = ar::BurgAllOrders(c, grid.max_order(), mean, &work);
  burg_work->Give(&work);
  for (int p = 1; p <= sequence.orders_completed; ++p) {
    m->models.push_back(
        ar::MakeArModel(sequence.phi[p - 1], sequence.innovation_variance(p - 1), mean, c.size()));
  }
  const int reached = static_cast<int>(m->models.size());
  m->fit_one_step.assign(reached, kNaN);
  m->fit_simulation.assign(reached, kNaN);
  m->used.assign(reached, false);
  m->centered_energy.assign(reached, -1.0);
  for (int order : grid.ar_orders) {
    const int used = UsedOrder(*m, order);
    if (used < 1 || m->used[used - 1]) continue;
    m->used[used - 1] = true;
    m->centered_energy[used - 1] = ar::CenteredTailEnergy(c, used);
    m->fit_one_step[used - 1] =
        ar::OneStepFitPercent(c, m->models[used - 1], m->centered_energy[used - 1]);
  }
}

/// The simulation fits of each used order over all components at once: their free runs are
/// latency-bound recursions that ar::SimulationFitPercents steps four at a time.
void FitSimulations(const ForEach& for_each, std::vector<ComponentModels>* components) {
  const int num_components = static_cast<int>(components->size());
  std::vector<int> used_orders;
  for (const ComponentModels& m : *components) {
    for (int p = 1; p <= static_cast<int>(m.used.size()); ++p) {
      if (m.used[p - 1] &&
          std::find(used_orders.begin(), used_orders.end(), p) == used_orders.end())
        used_orders.push_back(p);
    }
  }
  for_each(static_cast<int>(used_orders.size()), [&](int i) {
    const int p = used_orders[i];
    std::vector<ar::SimulationFitJob> jobs;
    std::vector<int> job_component;
    for (int k = 0; k < num_components; ++k) {
      const ComponentModels& m = (*components)[k];
      if (static_cast<int>(m.used.size()) < p || !m.used[p - 1]) continue;
      jobs.push_back(
          {m.signal->data(), m.signal->size(), &m.models[p - 1], m.centered_energy[p - 1]});
      job_component.push_back(k);
    }
    const std::vector<double> fit = ar::SimulationFitPercents(jobs);
    for (std::size_t j = 0; j < jobs.size(); ++j)
      (*components)[job_component[j]].fit_simulation[p - 1] = fit[j];
  });
}

/// The settings of one AR order, filtered together: points [begin, begin + count) of the sweep.
struct OrderBlock {
  int begin = 0;
  int count = 0;
  int order = 0;
};

/// GridSettings() lists each order's settings together: one block per order.
std::vector<OrderBlock> OrderBlocks(const std::vector<SweepSetting>& settings) {
  std::vector<OrderBlock> blocks;
  for (int i = 0; i < static_cast<int>(settings.size()); ++i) {
    if (i == 0 || settings[i].ar_order != settings[i - 1].ar_order)
      blocks.push_back({i, 0, settings[i].ar_order});
    ++blocks.back().count;
  }
  return blocks;
}

/// What every step of one order's evaluation reads.
struct SweepContext {
  const std::vector<ComponentModels>& components;
  const SweepOptions& options;
  double sample_rate_hz;
  const Eigen::VectorXd* truth;
  const ForEach& for_each;
  BufferPool& buffers;
  int num_imfs() const { return static_cast<int>(components.size()) - 1; }
};

/// Component m's filters for the block's settings (points[0..count)), at the highest stationary
/// order up to the block's; lower still while some setting's constant-gain loop would not be
/// stable on it (kalman::ConstantGainLoopStable), as ModelComponent does for `run`. *used receives
/// the order run.
std::unique_ptr<kalman::ArFilterBank> FilterBank(const SweepContext& context,
                                                 const ComponentModels& m, int order,
                                                 const SweepPoint* points, int count, int* used) {
  *used = UsedOrder(m, order);
  std::vector<kalman::ArKalmanOptions> kalman_options(count);
  for (;;) {
    const ar::ArModel& model = m.models[*used - 1];
    for (int j = 0; j < count; ++j)
      kalman_options[j] = SettingFilterOptions(m, model, points[j].setting, context.options);
    auto bank = std::make_unique<kalman::ArFilterBank>(
        *m.signal, model.phi, model.innovation_variance, m.white_noise, kalman_options,
        m.filter_variance_ok ? &m.filter_variance : nullptr);
    const std::vector<kalman::ArKalmanSummary> tried = bank->summaries();
    const bool unstable =
        std::any_of(tried.begin(), tried.end(), [](const auto& t) { return t.loop_unstable; });
    const int lower = LowerOrder(m, *used);
    if (!unstable || lower == 0) return bank;
    *used = lower;
  }
}

/// Every component's filter bank for the block (their time-varying phases run here; null for a
/// constant component, passed through), each point's per-component fit % and order, and the
/// first component whose filter failed a setting.
std::vector<std::unique_ptr<kalman::ArFilterBank>> FilterComponents(const SweepContext& context,
                                                                    const OrderBlock& block,
                                                                    SweepPoint* points) {
  const int num_components = static_cast<int>(context.components.size());
  std::vector<std::unique_ptr<kalman::ArFilterBank>> banks(num_components);
  for (int k = 0; k < num_components; ++k) {
    const ComponentModels& m = context.components[k];
    int used = 0;
    std::pair<double, double> fits = {kNaN, kNaN};
    if (!m.constant) {
      banks[k] = FilterBank(context, m, block.order, points, block.count, &used);
      fits = FitsOfOrder(m, used);
    }
    for (int j = 0; j < block.count; ++j) {
      points[j].fit_one_step_percent.push_back(fits.first);
      points[j].fit_simulation_percent.push_back(fits.second);
      points[j].ar_order_used.push_back(used);
    }
    if (m.constant) continue;
    const std::vector<kalman::ArKalmanSummary> filtered = banks[k]->summaries();
    for (int j = 0; j < block.count; ++j) {
      SweepPoint& point = points[j];
      if (HasResult(filtered[j].termination) || !HasResult(point.termination)) continue;
      point.termination = filtered[j].termination;
      point.message =
          ComponentName(k, context.num_imfs()) + ": Kalman filter: " + filtered[j].message;
    }
  }
  return banks;
}

/// The block's method-1 sums (eq. 12), one per setting, in component order. They are built one
/// range at a time in a buffer interleaved sample by sample (setting j's sample k at
/// (k - range) * count + j): four settings' filters then add their estimates with one vector
/// operation (kalman::ArFilterBank::AddRange), and the finished range, still in cache, is copied
/// out into each setting's series. Each range of every sum stays in cache while all components
/// add to it, in component order: the same additions, in the same order, as one pass per
/// component, so the sums are equal to the last bit.
std::vector<Eigen::VectorXd> SumComponents(
    const std::vector<ComponentModels>& components,
    const std::vector<std::unique_ptr<kalman::ArFilterBank>>& banks, int count, Eigen::Index n,
    BufferPool* buffers) {
  std::vector<Eigen::VectorXd> series(count);
  for (Eigen::VectorXd& v : series) v = buffers->Take(n);  // every sample is written below
  std::vector<double> range_sums(static_cast<std::size_t>(kSumRange) * count);
  std::vector<double*> sums(count);
  for (int j = 0; j < count; ++j) sums[j] = range_sums.data() + j;
  for (Eigen::Index range = 0; range < n; range += kSumRange) {
    const Eigen::Index end = std::min<Eigen::Index>(n, range + kSumRange);
    std::fill(range_sums.begin(), range_sums.end(), 0.0);
    for (std::size_t k = 0; k < components.size(); ++k) {
      if (banks[k]) {
        banks[k]->AddRange(range, end, sums, count, range);
        continue;
      }
      const Eigen::VectorXd& signal = *components[k].signal;
      for (Eigen::Index i = range; i < end; ++i) {
        for (int j = 0; j < count; ++j) range_sums[(i - range) * count + j] += signal[i];
      }
    }
    for (Eigen::Index i = range; i < end; ++i) {
      const double* from = range_sums.data() + (i - range) * count;
      for (int j = 0; j < count; ++j) series[j][i] = from[j];
    }
  }
  return series;
}

/// The block's settings (indices into points) whose filter diverged on some component
/// (FilterDiverged, as `run` checks it, from a mean square summed in another order: the two can
/// disagree only within rounding of the threshold).
std::vector<int> DivergedSettings(const std::vector<ComponentModels>& components,
                                  const std::vector<std::unique_ptr<kalman::ArFilterBank>>& banks,
                                  const SweepPoint* points, int count) {
  std::vector<std::vector<double>> mean_squares(components.size());
  for (std::size_t k = 0; k < components.size(); ++k) {
    if (banks[k]) mean_squares[k] = banks[k]->EstimateMeanSquares();
  }
  std::vector<int> diverged_settings;
  for (int j = 0; j < count; ++j) {
    if (!HasResult(points[j].termination)) continue;
    for (std::size_t k = 0; k < components.size(); ++k) {
      std::string diverged;
      if (banks[k] && FilterDiverged(mean_squares[k][j], components[k].variance, &diverged)) {
        diverged_settings.push_back(j);
        break;
      }
    }
  }
  return diverged_settings;
}

/// Component m filtered alone for `setting` from order *used down the stationary orders while the
/// filter breaks down (FilterBrokeDown). Returns the last filter run, *used its order; *broke_down
/// and *diverged say whether, and why, it broke down at every order tried.
kalman::ArKalmanResult FilterAlone(const ComponentModels& m, const SweepSetting& setting,
                                   const SweepOptions& options, int* used, bool* broke_down,
                                   std::string* diverged) {
  for (;;) {
    const ar::ArModel& model = m.models[*used - 1];
    kalman::ArKalmanResult filtered =
        kalman::FilterAr(*m.signal, model.phi, model.innovation_variance, m.white_noise,
                         SettingFilterOptions(m, model, setting, options));
    *broke_down = FilterBrokeDown(filtered, model.mean, m.variance, diverged);
    const int lower = LowerOrder(m, *used);
    if (!*broke_down || lower == 0) return filtered;
    *used = lower;
  }
}

/// A setting whose filter diverged on some component is filtered again alone, component by
/// component, and a diverged component gets the next lower stationary order until its filter
/// works, as ModelComponent does for `run`. kalman::FilterAr equals the bank's filter to the last
/// bit, and the sum runs in component order as SumComponents' does, so the other components
/// contribute exactly what they did. Only if no order down to AR(1) works is the setting a
/// numerical failure naming the component.
void RefilterAlone(const SweepContext& context, SweepPoint* point, Eigen::VectorXd* series) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(series->size());
  for (std::size_t k = 0; k < context.components.size(); ++k) {
    const ComponentModels& m = context.components[k];
    if (m.constant) {
      sum += *m.signal;
      continue;
    }
    const std::string name = ComponentName(static_cast<int>(k), context.num_imfs());
    int used = point->ar_order_used[k];
    bool broke_down = false;
    std::string diverged;
    const kalman::ArKalmanResult filtered =
        FilterAlone(m, point->setting, context.options, &used, &broke_down, &diverged);
    if (broke_down) {
      point->termination = Termination::kNumericalFailure;
      point->message = name + ": Kalman filter " + diverged +
                       " at every stationary order down to AR(" + std::to_string(used) + ")";
      return;
    }
    if (!HasResult(filtered.summary.termination)) {
      point->termination = filtered.summary.termination;
      point->message = name + ": Kalman filter: " + filtered.summary.message;
      return;
    }
    sum += filtered.smoothed.size() > 0 ? filtered.smoothed : filtered.filtered;
    if (used != point->ar_order_used[k]) {
      const auto [fit_one_step, fit_simulation] = FitsOfOrder(m, used);
      point->fit_one_step_percent[k] = fit_one_step;
      point->fit_simulation_percent[k] = fit_simulation;
      point->ar_order_used[k] = used;
    }
  }
  *series = std::move(sum);
}

/// Every setting of one AR order at once: the settings share the models, so one
/// kalman::ArFilterBank per component runs their constant-gain loops side by side (ar_kalman.h)
/// and adds each output to its setting's method-1 sum, in component order; then each setting's
/// Allan table, noise terms and RMS error. Writes only the block's points.
void EvaluateOrder(const SweepContext& context, const OrderBlock& block,
                   const std::vector<SweepSetting>& settings, SweepResult* out) {
  const auto filter_start = std::chrono::steady_clock::now();
  SweepPoint* points = out->points.data() + block.begin;
  for (int j = 0; j < block.count; ++j) {
    points[j].setting = settings[block.begin + j];
    points[j].termination = Termination::kSuccess;
  }
  const std::vector<std::unique_ptr<kalman::ArFilterBank>> banks =
      FilterComponents(context, block, points);
  std::vector<Eigen::VectorXd> series =
      SumComponents(context.components, banks, block.count, out->base.preprocessed.signal.size(),
                    &context.buffers);
  const std::vector<int> redo = DivergedSettings(context.components, banks, points, block.count);
  context.for_each(static_cast<int>(redo.size()),
                   [&](int r) { RefilterAlone(context, &points[redo[r]], &series[redo[r]]); });
  // The shared filtering time, split evenly among the order's settings.
  const double filter_seconds = SecondsSince(filter_start) / block.count;
  context.for_each(block.count, [&](int j) {
    const auto setting_start = std::chrono::steady_clock::now();
    SweepPoint& point = points[j];
    if (!HasResult(point.termination)) return;
    const bool scored =
        ScoreSignal(series[j], context.sample_rate_hz, context.options, out->base.preprocessed,
                    context.truth, &context.buffers, &point);
    context.buffers.Give(&series[j]);  // the series is not kept: the other blocks reuse it
    if (!scored) return;
    point.termination = Termination::kSuccess;
    point.seconds = filter_seconds + SecondsSince(setting_start);
  });
  for (Eigen::VectorXd& s : series) context.buffers.Give(&s);  // those of failed settings
}

/// Every grid setting, one AR order's block at a time (EvaluateOrder). Highest orders first: their
/// filters cost the most (O(p) per sample, O(p^2) per time-varying step), and started last they
/// leave one thread alone at the end. Each block writes only its own settings, so the order of the
/// blocks does not change any number.
void EvaluateGrid(const SweepContext& context, SweepResult* out) {
  const std::vector<SweepSetting> settings = GridSettings(context.options.grid);
  out->points.resize(settings.size());
  const std::vector<OrderBlock> blocks = OrderBlocks(settings);
  const int num_blocks = static_cast<int>(blocks.size());
  context.for_each(num_blocks, [&](int reversed) {
    EvaluateOrder(context, blocks[num_blocks - 1 - reversed], settings, out);
  });
}

}  // namespace

bool SweepOptions::IsValid(std::string* error) const {
  return method.IsValid(error) && grid.IsValid(error);
}

SweepResult RunSweep(const Eigen::VectorXd& x, double sample_rate_hz, const SweepOptions& options,
                     const Eigen::VectorXd* truth, const ForEach& for_each) {
  SweepResult out;
  if (!CheckInputs(x, options, truth, &out.summary)) return out;
  const auto decompose_start = std::chrono::steady_clock::now();
  PreprocessAndDecompose(x, sample_rate_hz, options.method, &out.base);
  out.summary.decompose_seconds = SecondsSince(decompose_start);
  if (!HasResult(out.base.summary.termination)) {
    out.summary.termination = out.base.summary.termination;
    out.summary.message = out.base.summary.message;
    return out;
  }
  const int num_imfs = static_cast<int>(out.base.decomposition.imfs.size());
  out.summary.num_imfs = num_imfs;

  const auto models_start = std::chrono::steady_clock::now();
  std::vector<ComponentModels> components = SetUpComponents(out.base);
  IdlePool<ar::BurgWork> burg_work;
  for_each(num_imfs + 1, [&](int k) { FitAllOrders(options.grid, &burg_work, &components[k]); });
  burg_work.Release();
  FitSimulations(for_each, &components);
  out.summary.models_seconds = SecondsSince(models_start);
  for (int k = 0; k <= num_imfs; ++k) {
    if (!components[k].constant && components[k].models.empty()) {
      out.summary.termination = Termination::kNumericalFailure;
      out.summary.message = ComponentName(k, num_imfs) + ": Burg produced no model";
      return out;
    }
  }

  BufferPool buffers;
  EvaluateGrid({components, options, sample_rate_hz, truth, for_each, buffers}, &out);
  buffers.Release();  // (the reference filters need their own memory)
  EvaluateReferences(sample_rate_hz, options, truth, for_each, &buffers, &out);
  for (const SweepPoint& point : out.points)
    out.summary.settings_ok += HasResult(point.termination);
  out.summary.termination =
      out.summary.settings_ok > 0 ? Termination::kSuccess : Termination::kNumericalFailure;
  out.summary.message = std::to_string(out.summary.settings_ok) + " of " +
                        std::to_string(out.points.size()) + " settings evaluated";
  return out;
}

int RankAmongGrid(const std::vector<SweepPoint>& points, const SweepPoint& reference,
                  const std::string& criterion) {
  if (!HasResult(reference.termination)) return -1;
  const double value = CriterionValue(reference, criterion);
  if (std::isnan(value)) return -1;
  const bool larger_is_better = criterion == "fit";
  int better = 0;
  for (const SweepPoint& p : points) {
    if (!HasResult(p.termination)) continue;
    const double v = CriterionValue(p, criterion);
    if (!std::isnan(v) && (larger_is_better ? v > value : v < value)) ++better;
  }
  return better;
}

const std::vector<std::string>& RankCriteria() {
  static const std::vector<std::string> criteria = {"rms_error", "q", "n", "b", "k", "r", "fit"};
  return criteria;
}

double CriterionValue(const SweepPoint& point, const std::string& criterion) {
  if (criterion == "rms_error") return point.rms_error;
  if (criterion == "fit") {
    double sum = 0.0;
    int count = 0;
    for (double f : point.fit_one_step_percent) {
      if (std::isfinite(f)) sum += f, ++count;
    }
    return count > 0 ? sum / count : kNaN;
  }
  const allan::NoiseTermsEngineering e = allan::ToEngineeringUnits(point.allan.noise.terms);
  if (criterion == "q") return e.q_arcsec;
  if (criterion == "n") return e.n_deg_sqrt_h;
  if (criterion == "b") return e.b_deg_h;
  if (criterion == "k") return e.k_deg_h_sqrt_h;
  if (criterion == "r") return e.r_deg_h2;
  throw std::invalid_argument("unknown ranking criterion '" + criterion + "'");
}

std::vector<int> RankSweep(const std::vector<SweepPoint>& points, const std::string& criterion) {
  const bool larger_is_better = criterion == "fit";
  std::vector<int> order;
  std::vector<double> value(points.size(), kNaN);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!HasResult(points[i].termination)) continue;
    value[i] = CriterionValue(points[i], criterion);
    order.push_back(static_cast<int>(i));
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const bool a_nan = std::isnan(value[a]), b_nan = std::isnan(value[b]);
    if (a_nan || b_nan) return !a_nan && b_nan;
    return larger_is_better ? value[a] > value[b] : value[a] < value[b];
  });
  return order;
}

}  // namespace fogpipe::method
