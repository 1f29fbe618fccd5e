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
#include "algorithms/common/units.h"
#include "algorithms/kalman/ar_kalman.h"
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

/// The Kalman options of one setting's filter on component c with `model` (one of c's models).
kalman::ArKalmanOptions SettingFilterOptions(const ComponentModels& c, const ar::ArModel& model,
                                             const SweepSetting& setting,
                                             const SweepOptions& options) {
  kalman::ArKalmanOptions o = options.method.component.kalman;
  o.q_scale = setting.default_rule ? 1.0 : setting.q_scale;
  o.r_scale = setting.default_rule ? 1.0 : setting.r_scale;
  o.mean = model.mean;
  o.max_time_varying_steps = kSweepTimeVaryingSteps;
  // Grid settings: q referred to sigma_e^2, R to the white share (sweep_grid.h); the default
  // rule: exactly ModelComponent()'s (white_noise.h, ApplyFilterNoise).
  if (setting.default_rule) {
    const FilterNoise noise = ComponentFilterNoise(
        options.method.component.noise_rule, c.white_noise, c.variance, model.innovation_variance);
    ApplyFilterNoise(noise, &o);
    if (o.r < 0.0) o.r = noise.r;
  } else {
    o.q = model.innovation_variance;
    if (o.r < 0.0) o.r = c.white_noise;
  }
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

/// The reference filters on the sweep's preprocessed signal, each scored like a grid setting.
void EvaluateReferences(double sample_rate_hz, const SweepOptions& options,
                        const Eigen::VectorXd* truth, const ForEach& for_each, SweepResult* out) {
  const auto start = std::chrono::steady_clock::now();
  RunReferenceFilters(sample_rate_hz, options.method, for_each, &out->base);
  const int count = static_cast<int>(out->base.reference.size());
  const double filter_seconds = SecondsSince(start) / std::max(1, count);
  out->reference.assign(count, SweepReference());
  const Preprocessed& pre = out->base.preprocessed;
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
    r.point.allan.allan = allan::ComputeAllan(o.signal, sample_rate_hz, options.method.allan);
    if (!HasResult(r.point.allan.allan.summary.termination)) {
      r.point.termination = r.point.allan.allan.summary.termination;
      r.point.message = "Allan variance: " + r.point.allan.allan.summary.message;
      return;
    }
    r.point.allan.noise = allan::FitNoiseTerms(r.point.allan.allan.table, options.method.noise_fit);
    if (truth != nullptr) {
      const Eigen::Index n = o.signal.size();
      r.point.rms_error = std::sqrt(((o.signal.array() + pre.mean_removed) -
                                     truth->segment(pre.summary.dropped_samples, n).array())
                                        .square()
                                        .mean());
    }
    r.point.seconds = filter_seconds + SecondsSince(allan_start);
  });
  // The signals are not kept (the sweep stores scores only).
  for (ReferenceEvaluation& e : out->base.reference) e.output.signal = Eigen::VectorXd();
}

}  // namespace

bool SweepOptions::IsValid(std::string* error) const {
  return method.IsValid(error) && grid.IsValid(error);
}

SweepResult RunSweep(const Eigen::VectorXd& x, double sample_rate_hz, const SweepOptions& options,
                     const Eigen::VectorXd* truth, const ForEach& for_each) {
  SweepResult out;
  std::string error;
  if (!options.IsValid(&error)) {
    out.summary.termination = Termination::kInvalidOptions;
    out.summary.message = error;
    return out;
  }
  if (truth != nullptr && truth->size() != x.size()) {
    out.summary.termination = Termination::kInvalidOptions;
    out.summary.message = "the true rate has " + std::to_string(truth->size()) +
                          " samples, the signal " + std::to_string(x.size());
    return out;
  }
  auto start = std::chrono::steady_clock::now();
  PreprocessAndDecompose(x, sample_rate_hz, options.method, &out.base);
  out.summary.decompose_seconds = SecondsSince(start);
  if (!HasResult(out.base.summary.termination)) {
    out.summary.termination = out.base.summary.termination;
    out.summary.message = out.base.summary.message;
    return out;
  }
  const emd::EmdResult& emd_result = out.base.decomposition;
  const Eigen::VectorXd& signal = out.base.preprocessed.signal;
  const int num_imfs = static_cast<int>(emd_result.imfs.size());
  const int num_components = num_imfs + 1;
  out.summary.num_imfs = num_imfs;

  // R per component exactly as ModelComponents() shares it (white_noise.h).
  std::vector<ComponentModels> components(num_components);
  for (int k = 0; k < num_components; ++k) {
    components[k].signal = k < num_imfs ? &emd_result.imfs[k] : &emd_result.residue;
  }
  const std::vector<double> variances = ComponentVariances(emd_result);
  const std::vector<double> r = ShareWhiteNoise(
      EstimateWhiteNoiseLevels(signal), ComponentPeriods(emd_result, signal.size()), variances);

  // One Burg recursion per component up to the largest order; fit % per order.
  start = std::chrono::steady_clock::now();
  const int max_order = options.grid.max_order();
  for_each(num_components, [&](int k) {
    ComponentModels& m = components[k];
    const Eigen::VectorXd& c = *m.signal;
    m.white_noise = r[k];
    m.variance = variances[k];
    m.constant = c.size() > 0 && (c.array() == c[0]).all();
    if (m.constant) return;
    m.filter_variance_ok = kalman::FilterInputVariance(c, &m.filter_variance);
    const double mean = c.mean();
    const ar::OrderSequence sequence = ar::BurgAllOrders(c, max_order, mean);
    for (int p = 1; p <= sequence.orders_completed; ++p) {
      m.models.push_back(ar::MakeArModel(sequence.phi[p - 1], sequence.innovation_variance(p - 1),
                                         mean, c.size()));
    }
    // One-step fit % only for the orders some setting uses: min(p, orders reached) for every p of
    // the grid. (The simulation fits below, across components.)
    const int reached = static_cast<int>(m.models.size());
    m.fit_one_step.assign(reached, kNaN);
    m.fit_simulation.assign(reached, kNaN);
    m.used.assign(reached, false);
    m.centered_energy.assign(reached, -1.0);
    for (int order : options.grid.ar_orders) {
      const int used = UsedOrder(m, order);
      if (used < 1 || m.used[used - 1]) continue;
      m.used[used - 1] = true;
      m.centered_energy[used - 1] = ar::CenteredTailEnergy(c, used);
      m.fit_one_step[used - 1] =
          ar::OneStepFitPercent(c, m.models[used - 1], m.centered_energy[used - 1]);
    }
  });
  // The simulation fits of each used order over all components at once: their free runs are
  // latency-bound recursions that ar::SimulationFitPercents steps four at a time.
  std::vector<int> used_orders;
  for (int k = 0; k < num_components; ++k) {
    for (int p = 1; p <= static_cast<int>(components[k].used.size()); ++p) {
      if (components[k].used[p - 1] &&
          std::find(used_orders.begin(), used_orders.end(), p) == used_orders.end())
        used_orders.push_back(p);
    }
  }
  for_each(static_cast<int>(used_orders.size()), [&](int i) {
    const int p = used_orders[i];
    std::vector<ar::SimulationFitJob> jobs;
    std::vector<int> job_component;
    for (int k = 0; k < num_components; ++k) {
      ComponentModels& m = components[k];
      if (static_cast<int>(m.used.size()) < p || !m.used[p - 1]) continue;
      jobs.push_back(
          {m.signal->data(), m.signal->size(), &m.models[p - 1], m.centered_energy[p - 1]});
      job_component.push_back(k);
    }
    const std::vector<double> fit = ar::SimulationFitPercents(jobs);
    for (std::size_t j = 0; j < jobs.size(); ++j)
      components[job_component[j]].fit_simulation[p - 1] = fit[j];
  });
  out.summary.models_seconds = SecondsSince(start);
  for (int k = 0; k < num_components; ++k) {
    if (!components[k].constant && components[k].models.empty()) {
      out.summary.termination = Termination::kNumericalFailure;
      out.summary.message = ComponentName(k, num_imfs) + ": Burg produced no model";
      return out;
    }
  }

  // Per AR order, every q/R setting of that order at once: the settings share the models, so one
  // kalman::ArFilterBank per component runs their constant-gain loops side by side (ar_kalman.h)
  // and adds each output to its setting's method-1 sum, in component order.
  const std::vector<SweepSetting> settings = GridSettings(options.grid);
  out.points.resize(settings.size());
  std::vector<std::pair<int, int>> blocks;  // [begin, end) of each order's settings
  for (int i = 0; i < static_cast<int>(settings.size()); ++i) {
    if (i == 0 || settings[i].ar_order != settings[i - 1].ar_order) blocks.push_back({i, i});
    blocks.back().second = i + 1;
  }
  const long long dropped = out.base.preprocessed.summary.dropped_samples;
  const Eigen::Index n = signal.size();
  // Highest orders first: their filters cost the most (O(p) per sample, O(p^2) per time-varying
  // step), and started last they leave one thread alone at the end. Each block writes only its own
  // settings, so the order of the blocks does not change any number.
  const int num_blocks = static_cast<int>(blocks.size());
  for_each(num_blocks, [&](int reversed) {
    const int b = num_blocks - 1 - reversed;
    const auto filter_start = std::chrono::steady_clock::now();
    const int begin = blocks[b].first, count = blocks[b].second - blocks[b].first;
    const int order = settings[begin].ar_order;
    // The settings' method-1 sums are built one range at a time in a buffer interleaved sample by
    // sample (setting j's sample k at (k - range) * count + j): four settings' filters then add
    // their estimates with one vector operation (kalman::ArFilterBank::AddRange), and the finished
    // range, still in cache, is copied out into each setting's series for its Allan table.
    std::vector<Eigen::VectorXd> series(count);
    for (Eigen::VectorXd& v : series) v.resize(n);  // (not copies of one: each filled below)
    std::vector<double> range_sums(static_cast<std::size_t>(kSumRange) * count);
    std::vector<double*> sums(count);
    for (int j = 0; j < count; ++j) {
      sums[j] = range_sums.data() + j;
      out.points[begin + j].setting = settings[begin + j];
      out.points[begin + j].termination = Termination::kSuccess;
    }
    // Every component's filters of this order (their time-varying phases run here), then the
    // sums range by range: each range of every setting's sum stays in cache while all components
    // add to it, in component order (the same additions, in the same order, as one pass per
    // component: the sums are equal to the last bit).
    std::vector<std::unique_ptr<kalman::ArFilterBank>> banks(num_components);
    for (int k = 0; k < num_components; ++k) {
      const ComponentModels& m = components[k];
      if (m.constant) {
        for (int j = 0; j < count; ++j) {
          out.points[begin + j].fit_one_step_percent.push_back(kNaN);
          out.points[begin + j].fit_simulation_percent.push_back(kNaN);
          out.points[begin + j].ar_order_used.push_back(0);
        }
        continue;
      }
      // The highest stationary order up to the setting's; lower still while some setting's
      // constant-gain loop would not be stable on it (kalman::ConstantGainLoopStable), as
      // ModelComponent does for `run`.
      int used = UsedOrder(m, order);
      std::vector<kalman::ArKalmanOptions> kalman_options(count);
      for (;;) {
        const ar::ArModel& model = m.models[used - 1];
        for (int j = 0; j < count; ++j)
          kalman_options[j] = SettingFilterOptions(m, model, settings[begin + j], options);
        banks[k] = std::make_unique<kalman::ArFilterBank>(
            *m.signal, model.phi, model.innovation_variance, m.white_noise, kalman_options,
            m.filter_variance_ok ? &m.filter_variance : nullptr);
        const std::vector<kalman::ArKalmanSummary> tried = banks[k]->summaries();
        const bool unstable =
            std::any_of(tried.begin(), tried.end(), [](const auto& t) { return t.loop_unstable; });
        const int lower = used > 1 ? UsedOrder(m, used - 1) : 0;
        if (!unstable || lower < 1 || lower >= used) break;
        used = lower;
      }
      const auto [fit_one_step, fit_simulation] = FitsOfOrder(m, used);
      for (int j = 0; j < count; ++j) {
        out.points[begin + j].fit_one_step_percent.push_back(fit_one_step);
        out.points[begin + j].fit_simulation_percent.push_back(fit_simulation);
        out.points[begin + j].ar_order_used.push_back(used);
      }
      const std::vector<kalman::ArKalmanSummary> filtered = banks[k]->summaries();
      for (int j = 0; j < count; ++j) {
        SweepPoint& point = out.points[begin + j];
        if (HasResult(filtered[j].termination) || !HasResult(point.termination)) continue;
        point.termination = filtered[j].termination;
        point.message = ComponentName(k, num_imfs) + ": Kalman filter: " + filtered[j].message;
      }
    }
    for (Eigen::Index range = 0; range < n; range += kSumRange) {
      const Eigen::Index end = std::min<Eigen::Index>(n, range + kSumRange);
      std::fill(range_sums.begin(), range_sums.end(), 0.0);
      for (int k = 0; k < num_components; ++k) {
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
    // A setting whose filter diverged on some component (component.h, FilterDiverged, as `run`
    // checks it, from a mean square summed in another order: the two can disagree only within
    // rounding of the threshold) is filtered again alone, component by component, and a diverged
    // component gets the next lower stationary order until its filter works, as ModelComponent
    // does for `run`. kalman::FilterAr equals the bank's filter to the last bit, and the sum runs
    // in component order as the ranges above do, so the other components contribute exactly what
    // they did. Only if no order down to AR(1) works is the setting a numerical failure naming
    // the component.
    std::vector<std::vector<double>> mean_squares(num_components);
    for (int k = 0; k < num_components; ++k) {
      if (banks[k]) mean_squares[k] = banks[k]->EstimateMeanSquares();
    }
    std::vector<int> redo;
    for (int j = 0; j < count; ++j) {
      if (!HasResult(out.points[begin + j].termination)) continue;
      for (int k = 0; k < num_components; ++k) {
        std::string diverged;
        if (banks[k] && FilterDiverged(mean_squares[k][j], components[k].variance, &diverged)) {
          redo.push_back(j);
          break;
        }
      }
    }
    for_each(static_cast<int>(redo.size()), [&](int r) {
      const int j = redo[r];
      SweepPoint& point = out.points[begin + j];
      Eigen::VectorXd sum = Eigen::VectorXd::Zero(n);
      for (int k = 0; k < num_components; ++k) {
        const ComponentModels& m = components[k];
        if (!banks[k]) {
          sum += *m.signal;
          continue;
        }
        int used = point.ar_order_used[k];
        kalman::ArKalmanResult filtered;
        std::string diverged;
        for (;;) {
          const ar::ArModel& model = m.models[used - 1];
          filtered =
              kalman::FilterAr(*m.signal, model.phi, model.innovation_variance, m.white_noise,
                               SettingFilterOptions(m, model, point.setting, options));
          const bool bad = FilterBrokeDown(filtered, model.mean, m.variance, &diverged);
          const int lower = used > 1 ? UsedOrder(m, used - 1) : 0;
          if (!bad || lower < 1 || lower >= used) {
            if (bad) {
              point.termination = Termination::kNumericalFailure;
              point.message = ComponentName(k, num_imfs) + ": Kalman filter " + diverged +
                              " at every stationary order down to AR(" + std::to_string(used) + ")";
            }
            break;
          }
          used = lower;
        }
        if (!HasResult(point.termination)) return;
        if (!HasResult(filtered.summary.termination)) {
          point.termination = filtered.summary.termination;
          point.message =
              ComponentName(k, num_imfs) + ": Kalman filter: " + filtered.summary.message;
          return;
        }
        sum += filtered.smoothed.size() > 0 ? filtered.smoothed : filtered.filtered;
        if (used != point.ar_order_used[k]) {
          const auto [fit_one_step, fit_simulation] = FitsOfOrder(m, used);
          point.fit_one_step_percent[k] = fit_one_step;
          point.fit_simulation_percent[k] = fit_simulation;
          point.ar_order_used[k] = used;
        }
      }
      series[j] = std::move(sum);
    });
    // The shared filtering time, split evenly among the order's settings.
    const double filter_seconds = SecondsSince(filter_start) / count;
    for_each(count, [&](int j) {
      const auto setting_start = std::chrono::steady_clock::now();
      SweepPoint& point = out.points[begin + j];
      if (!HasResult(point.termination)) return;
      point.allan.allan = allan::ComputeAllan(series[j], sample_rate_hz, options.method.allan);
      if (!HasResult(point.allan.allan.summary.termination)) {
        point.termination = point.allan.allan.summary.termination;
        point.message = "Allan variance: " + point.allan.allan.summary.message;
        return;
      }
      point.allan.noise = allan::FitNoiseTerms(point.allan.allan.table, options.method.noise_fit);
      point.rms_error = kNaN;
      if (truth != nullptr) {
        point.rms_error = std::sqrt(((series[j].array() + out.base.preprocessed.mean_removed) -
                                     truth->segment(dropped, n).array())
                                        .square()
                                        .mean());
      }
      series[j] = Eigen::VectorXd();  // the series is not kept: free it for the other blocks
      point.termination = Termination::kSuccess;
      point.seconds = filter_seconds + SecondsSince(setting_start);
    });
  });
  EvaluateReferences(sample_rate_hz, options, truth, for_each, &out);
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
