#include "algorithms/model/imf_view.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "algorithms/allan/edf.h"
#include "algorithms/ar/fit_ar.h"
#include "algorithms/model/narrow_band.h"
#include "algorithms/model/spectrum.h"
#include "algorithms/simulation/gyro_simulator.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::model {
namespace {

double Pearson(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::ArrayXd x = a.array() - a.mean(), y = b.array() - b.mean();
  const double sxx = x.square().sum(), syy = y.square().sum();
  return (sxx > 0 && syy > 0) ? (x * y).sum() / std::sqrt(sxx * syy) : 0.0;
}

// Fractional-octave moving average of a one-sided spectrum: bin j is replaced by the mean over the
// bins in [f_j 2^(-w/2), f_j 2^(w/2)] (at least bin j itself). Prefix sums: O(bins).
std::vector<double> OctaveSmooth(const std::vector<double>& psd, double octaves) {
  std::vector<double> prefix_sums(psd.size() + 1, 0.0), out(psd.size(), 0.0);
  for (size_t j = 0; j < psd.size(); ++j) prefix_sums[j + 1] = prefix_sums[j] + psd[j];
  const double half = std::pow(2.0, 0.5 * octaves);
  for (size_t j = 1; j < psd.size(); ++j) {
    const size_t lo = std::max<size_t>(1, static_cast<size_t>(std::floor(j / half)));
    const size_t hi = std::min(psd.size() - 1, static_cast<size_t>(std::ceil(j * half)));
    out[j] = (prefix_sums[hi + 1] - prefix_sums[lo]) / static_cast<double>(hi + 1 - lo);
  }
  return out;
}

// Per-IMF energies of the fitted model: `reference_realizations` simulations of the fitted
// stochastic terms at the decimated rate (fogpipe::simulation, IEEE Std 952-1997 Annex C laws,
// fixed seeds), decomposed with the same EMD options. The expectation is the mean of ln energy
// over the realizations (the test is on the log scale, so the centre is E[ln energy], not
// ln E[energy]: they differ by ~1 / nu, which matters on the slow IMFs); the spread of ln energy
// over the realizations calibrates the EDF (see ComputeImfView); the smoothed periodogram P_k of
// each reference IMF gives nu_k = 2 n (int P_k)^2 / (fs int P_k^2).
struct Reference {
  std::vector<double> energy;   // exp(mean of ln energy) over the realizations that reached k
  std::vector<double> log_var;  // sample variance of ln energy over those realizations
  std::vector<int> count;       // how many realizations reached IMF k
  std::vector<double> edf;
  std::vector<std::vector<double>> psd;  // mean smoothed periodogram of IMF k, (rad/s)^2 / Hz
  std::string error;
};

// The reference's narrow bands draw from streams of their own (the simulator numbers its streams
// from small integers).
constexpr std::uint64_t kNarrowBandStream = 0x6E6172726F770000ULL;

simulation::GyroErrorModel NoiseOf(const StochasticModel& model) {
  simulation::GyroErrorModel errors;
  if (model.Has(Term::kWhite)) errors.n_rad_sqrt_s = model.n_rad_sqrt_s;
  if (model.Has(Term::kQuantization)) errors.q_rad = model.q_rad;
  if (model.Has(Term::kBiasInstability)) errors.b_rad_s = model.b_rad_s;
  if (model.Has(Term::kRateRandomWalk)) errors.k_rad_s_sqrt_s = model.k_rad_s_sqrt_s;
  if (model.Has(Term::kRateRamp)) errors.r_rad_s2 = model.r_rad_s2;
  if (model.Has(Term::kGaussMarkov) && model.gm_sigma_rad_s > 0 && model.gm_correlation_time_s > 0)
    errors.gauss_markov.push_back({model.gm_sigma_rad_s, model.gm_correlation_time_s});
  return errors;
}

// n samples at fs, the block means of `decimation` samples at fs * decimation: what the view
// decomposes. The power-law and Gauss-Markov terms are simulated at fs directly (their laws hold
// for block means at the lower rate); a narrow band is simulated at the original rate and averaged
// like the residual, so that the block means attenuate and alias it as they do the data.
Reference ModelReference(long n, double fs, long decimation, const StochasticModel& model,
                         const ImfViewOptions& options) {
  Reference ref;
  std::vector<double> psd_sum, psd_square_sum;
  std::vector<std::vector<double>> logs;  // [imf][realization]
  double bin_width_hz = 0;
  for (int realization = 0; realization < options.reference_realizations; ++realization) {
    simulation::GyroSimulatorOptions simulator_options;
    simulator_options.sample_rate_hz = fs;
    simulator_options.duration_s = n / fs;
    simulator_options.seed = simulation::DeriveSeed(options.reference_seed, realization);
    simulator_options.errors = NoiseOf(model);
    const simulation::SimulatedRecording simulated = simulation::SimulateGyro(simulator_options);
    if (!HasResult(simulated.summary.termination)) {
      ref.error = simulated.summary.message;
      return ref;
    }
    Eigen::VectorXd rate =
        simulated.rate_rad_s.head(std::min<long>(n, simulated.rate_rad_s.size()));
    // The model's narrow bands, which the simulator's error model has no term for, each from a
    // stream of its own.
    for (size_t b = 0; b < model.bands.size(); ++b)
      rate += SimulateNarrowBand(
          model.bands[b], rate.size(), fs * decimation,
          simulation::DeriveSeed(simulator_options.seed, kNarrowBandStream + b), decimation);
    rate.array() -= rate.mean();
    const emd::EmdResult decomposition = emd::Decompose(rate, options.emd);
    for (size_t k = 0; k < decomposition.imfs.size(); ++k) {
      if (logs.size() <= k) {
        logs.emplace_back();
        psd_sum.push_back(0.0);
        psd_square_sum.push_back(0.0);
        ref.psd.emplace_back();
      }
      logs[k].push_back(std::log(std::max(decomposition.imf_info[k].energy, 1e-300)));
      const Spectrum spectrum = Periodogram(decomposition.imfs[k], fs, 1);
      bin_width_hz = spectrum.frequency_hz.size() > 1 ? spectrum.frequency_hz[1] : 0.0;
      const std::vector<double> smoothed = OctaveSmooth(spectrum.psd, options.smoothing_octaves);
      if (ref.psd[k].empty()) ref.psd[k].assign(smoothed.size(), 0.0);
      for (size_t j = 1; j < smoothed.size(); ++j) {
        psd_sum[k] += smoothed[j];
        psd_square_sum[k] += smoothed[j] * smoothed[j];
        ref.psd[k][j] += smoothed[j];
      }
    }
  }
  // An IMF index that only some realizations reached is averaged over those that did.
  for (size_t k = 0; k < logs.size(); ++k) {
    const int num_reached = static_cast<int>(logs[k].size());
    double mean = 0, sum_squares = 0;
    for (double log_energy : logs[k]) mean += log_energy / num_reached;
    for (double log_energy : logs[k]) sum_squares += (log_energy - mean) * (log_energy - mean);
    ref.energy.push_back(std::exp(mean));
    ref.log_var.push_back(num_reached > 1 ? sum_squares / (num_reached - 1) : 0.0);
    ref.count.push_back(num_reached);
    for (double& density : ref.psd[k]) density /= num_reached;
    // On bins of width df: nu = 2 n (sum P df)^2 / (fs sum P^2 df) for one realization; p1, p2
    // add up c realizations, hence the division by c.
    ref.edf.push_back(psd_square_sum[k] > 0 ? 2.0 * n * bin_width_hz * psd_sum[k] * psd_sum[k] /
                                                  (fs * psd_square_sum[k] * num_reached)
                                            : 0.0);
  }
  return ref;
}

// EDF of the energy in the octave band of period T under the model, as the EDF of the
// overlapping Allan variance at tau = T / 2 (Greenhall & Riley 2003): an Allan variance is the
// power in an octave band around 1 / (2 tau), and Greenhall's EDF knows what the IMF spectrum does
// not: rate random walk and flicker noise are not stationary, and their band energies fluctuate far
// more than a stationary band-pass process of the same spectrum. The terms are independent, so
// nu = (sum A_i)^2 / sum (A_i^2 / nu_i) with A_i each term's Allan variance.
double AllanBandEdf(const StochasticModel& model, double period_s, double fs, long n) {
  const double tau = 0.5 * period_s;
  const long long averaging_factor = std::max(1LL, std::llround(tau * fs));
  double sum = 0, weighted = 0;
  for (Term term : model.terms) {
    int alpha = 0;  // white FM
    if (term == Term::kQuantization) alpha = 2;
    if (term == Term::kBiasInstability) alpha = -1;
    if (term == Term::kRateRandomWalk || term == Term::kRateRamp)
      alpha = -2;  // ramp: steepest allowed
    if (term == Term::kGaussMarkov && tau < model.gm_correlation_time_s) alpha = -2;
    const double term_avar = TermAllanVariance(model, term, averaging_factor / fs);
    const double nu = allan::GreenhallEdf(alpha, 2, averaging_factor, n + 1, true, true);
    if (!(term_avar > 0) || !(nu > 0)) continue;
    sum += term_avar;
    weighted += term_avar * term_avar / nu;
  }
  return weighted > 0 ? sum * sum / weighted : std::numeric_limits<double>::quiet_NaN();
}

// Variance of ln(expected energy) from the fitted parameters' standard errors, at the IMF's
// scale: each term's Allan variance at tau = T / 2 with its parameter raised by one standard error,
// relative to the model's, in quadrature (correlations ignored). At long periods this dominates:
// bias instability and rate random walk are fitted from a few long-tau Allan points.
double ParameterLogVariance(const StochasticModel& model, double period_s) {
  const double tau = 0.5 * period_s;
  const double total = ModelAllanVariance(model, tau);
  if (!(total > 0)) return 0.0;
  double variance = 0;
  for (Term term : model.terms) {
    StochasticModel raised = model;
    if (term == Term::kWhite) raised.n_rad_sqrt_s += model.n_se;
    if (term == Term::kQuantization) raised.q_rad += model.q_se;
    if (term == Term::kBiasInstability) raised.b_rad_s += model.b_se;
    if (term == Term::kRateRandomWalk) raised.k_rad_s_sqrt_s += model.k_se;
    if (term == Term::kRateRamp) raised.r_rad_s2 += model.r_se;
    if (term == Term::kGaussMarkov) raised.gm_sigma_rad_s += model.gm_sigma_se;
    const double relative_change =
        (TermAllanVariance(raised, term, tau) - TermAllanVariance(model, term, tau)) / total;
    variance += relative_change * relative_change;
  }
  return variance;
}

// One test of the IMF view: its p-value and the IMF it is about.
struct ImfTest {
  double p;
  int imf;
};

// The IMF view's failure step: Holm's (1979) step-down over all its tests at level `alpha`, the
// per-test level and critical values it implies, and the IMFs it flags.
void FlagImfs(const std::vector<ImfTest>& tests, double alpha, int num_imfs, ImfView* view) {
  const int num_tests = static_cast<int>(tests.size());
  std::vector<double> sorted_p;
  for (const ImfTest& test : tests) sorted_p.push_back(test.p);
  std::sort(sorted_p.begin(), sorted_p.end());
  int rejected = 0;
  while (rejected < num_tests && sorted_p[rejected] <= alpha / (num_tests - rejected)) ++rejected;
  view->test_level = alpha / std::max(1, num_tests - std::max(rejected, 1) + 1);
  view->critical = NormalToStudent(UpperTailZ(view->test_level), view->reference_dof);
  view->aux_critical = UpperTailZ(0.5 * view->test_level);
  view->flagged.assign(num_imfs, 0);
  for (const ImfTest& test : tests)
    if (test.p <= view->test_level) view->flagged[test.imf] = 1;
  for (int flag : view->flagged) view->summary.num_flagged += flag;
  view->summary.message = std::to_string(view->summary.num_flagged) + " of " +
                          std::to_string(view->summary.num_scored) + " scored IMFs carry misfit";
}

}  // namespace

bool ImfViewOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* message) {
    if (error) *error = message;
    return false;
  };
  if (max_samples < 64) return fail("imf.max_samples must be >= 64");
  if (reference_realizations < 1) return fail("imf.reference_realizations must be >= 1");
  if (!(smoothing_octaves >= 0)) return fail("imf.smoothing_octaves must be >= 0");
  if (!(relative_floor >= 0 && relative_floor < 1)) return fail("imf.relative_floor in [0, 1)");
  if (!(alpha > 0 && alpha < 1)) return fail("imf.alpha must be in (0, 1)");
  if (!(min_cycles > 0)) return fail("imf.min_cycles must be > 0");
  if (!(min_shared_fraction >= 0 && min_shared_fraction <= 1))
    return fail("imf.min_shared_fraction in [0, 1]");
  if (max_ar_order < 1 || max_ar_order > ar::ArOptions::kMaxOrderLimit)
    return fail("imf.max_ar_order out of range");
  return emd.IsValid(error);
}

ImfView ComputeImfView(const Eigen::VectorXd& residual, double fs,
                       const std::vector<PreparedAux>& aux, const StochasticModel& model,
                       const ImfViewOptions& options) {
  ImfView view;
  std::string err;
  if (!options.IsValid(&err) || !(fs > 0)) {
    view.summary.termination = Termination::kInvalidOptions;
    view.summary.message = fs > 0 ? err : "sample_rate_hz must be > 0";
    return view;
  }
  const long n = residual.size();
  view.decimation = std::max(1L, (n + options.max_samples - 1) / options.max_samples);
  const long decimation = view.decimation;
  const double decimated_rate_hz = fs / decimation;
  view.sample_rate_hz = decimated_rate_hz;
  Eigen::VectorXd decimated = BlockMeans(residual, decimation);
  const long num_decimated = decimated.size();
  if (num_decimated < 64) {
    view.summary.termination = Termination::kInsufficientData;
    view.summary.message = "residual too short for the IMF view";
    return view;
  }
  decimated.array() -= decimated.mean();
  const emd::EmdResult decomposition = emd::Decompose(decimated, options.emd);
  if (!HasResult(decomposition.summary.termination) || decomposition.imfs.empty()) {
    view.summary.termination = decomposition.imfs.empty() ? Termination::kInsufficientData
                                                          : decomposition.summary.termination;
    view.summary.message = "EMD of the residual: " + decomposition.summary.message;
    return view;
  }
  // The EMD of the fitted noise, measured (for white noise: the dyadic law of Wu & Huang 2004).
  const Reference ref =
      ModelReference(num_decimated, decimated_rate_hz, decimation, model, options);
  if (!ref.error.empty() || ref.energy.empty()) {
    view.summary.termination = Termination::kInsufficientData;
    view.summary.message = "no reference decomposition of the fitted noise: " + ref.error;
    return view;
  }
  const double record_s = num_decimated / decimated_rate_hz;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const int num_imfs = static_cast<int>(decomposition.imfs.size());
  std::vector<double> parameter_log_variance(num_imfs, nan);
  for (int k = 0; k < num_imfs; ++k) {
    const emd::ImfInfo& info = decomposition.imf_info[k];
    const double period_s = info.mean_period_samples / decimated_rate_hz;
    view.mean_period_s.push_back(period_s);
    view.energy.push_back(info.energy);
    const bool in_ref = k < static_cast<int>(ref.energy.size()) && ref.energy[k] > 0;
    const double expected = in_ref ? ref.energy[k] : nan;
    // The smaller of the band-pass EDF of the reference IMF and the Allan band EDF (above).
    const double nu =
        in_ref
            ? std::fmin(ref.edf[k], AllanBandEdf(model, period_s, decimated_rate_hz, num_decimated))
            : nan;
    view.expected_energy.push_back(expected);
    view.ratio.push_back(in_ref ? info.energy / expected : nan);
    view.edf.push_back(nu);
    const bool scored =
        expected > 0 && nu > 0 && info.energy > 0 && record_s >= options.min_cycles * period_s;
    view.scored.push_back(scored ? 1 : 0);
    parameter_log_variance[k] = ParameterLogVariance(model, period_s);
    ar::ArOptions ar_options;
    ar_options.max_order = options.max_ar_order;
    const ar::ArFit fit = ar::FitAr(decomposition.imfs[k], ar_options);
    const bool ok = HasResult(fit.summary.termination);
    view.ar_order.push_back(ok ? fit.model.order : 0);
    view.ar_fit_percent.push_back(ok ? fit.diagnostics.fit_one_step_percent : nan);
  }
  view.summary.num_imfs = num_imfs;
  for (int scored_flag : view.scored) view.summary.num_scored += scored_flag;

  // Calibration of the EDF by the reference realizations: ln energy of one realization has
  // variance lambda * 2 / nu_k. Each scored IMF that every realization reached gives an estimate
  // s_k^2 nu_k / 2 ~ lambda chi2(R - 1) / (R - 1); their plain mean has (R - 1) x (count) degrees
  // of freedom (equal weights: weighting by 2 / nu_k would let the two slowest IMFs decide).
  // lambda captures what the EDF does not: EMD's mode mixing moves energy between neighbouring
  // IMFs, so an IMF's energy scatters more than that of a fixed band-pass filter (measured on
  // effect-free navigation-grade recordings: lambda ~ 1.2-2 on every IMF).
  const int num_realizations = options.reference_realizations;
  double lambda_sum = 0;
  int pooled = 0;
  for (int k = 0; k < num_imfs; ++k) {
    if (!view.scored[k] || ref.count[k] != num_realizations || num_realizations < 2) continue;
    lambda_sum += ref.log_var[k] * view.edf[k] / 2.0;
    ++pooled;
  }
  view.log_variance_ratio = pooled > 0 ? lambda_sum / pooled : 1.0;
  view.reference_dof =
      pooled > 0 ? pooled * (num_realizations - 1.0) : std::numeric_limits<double>::infinity();

  // Energy tests: t_k = ln(energy_k / E_k) / sd_k, sd_k^2 = lambda (2 / nu_k)(1 + 1 / R) + c^2 +
  // the parameters' share; Student t with the pooled dof (the variance is estimated), one-sided.
  std::vector<ImfTest> tests;
  for (int k = 0; k < num_imfs; ++k) {
    const double expected = view.expected_energy[k];
    const double log_sd =
        expected > 0 && view.edf[k] > 0
            ? std::sqrt(view.log_variance_ratio * 2.0 / view.edf[k] * (1.0 + 1.0 / ref.count[k]) +
                        options.relative_floor * options.relative_floor + parameter_log_variance[k])
            : nan;
    view.log_sd.push_back(log_sd);
    view.z.push_back(view.scored[k] ? std::log(view.energy[k] / expected) / log_sd : nan);
    if (view.scored[k])
      tests.push_back({UpperTailP(StudentToNormal(view.z[k], view.reference_dof)), k});
  }

  // Aux: Pearson r of each IMF x with each channel y (block-averaged like the residual) and with
  // its smoothed derivative, against "x is the fitted noise's IMF k, independent of y". Given y
  // and a stationary x of spectrum S_x, Var(sum x y) = int S_x |Y|^2 df, so on one-sided
  // periodogram bins r has variance 1 / n_eff, n_eff = 2 sum S_x sum P_y / sum S_x P_y, and
  // z = r sqrt(n_eff). This is Bartlett's (1935) n / sum_k rho_x(k) rho_y(k) written by Parseval
  // (Bretherton et al. 1999), and the variance of r over phase-randomised surrogates (Theiler et
  // al. 1992; Ebisuzaki 1997) of spectrum S_x: a slow IMF and a smooth 1-2 h temperature cycle
  // over 6 h share only ~10-60 independent values, far fewer than the IMF's own EDF. S_x is the
  // reference realizations' mean smoothed periodogram of IMF k, not the data IMF's own: under a
  // thermal effect the data IMF's spectrum is the temperature's, and the null variance it gives
  // would hide the effect (r ~ 0.95 with n_eff ~ 3). Two-sided. An IMF is tested against a
  // channel only where they share spectrum: at least `min_shared_fraction` of the channel's
  // variance inside the IMF's band (the bins where S_x is above a quarter of its peak). Elsewhere
  // r is carried by the far tails of S_x, which 4 realizations do not estimate and EMD end effects
  // dominate (measured: mid-period IMFs against the temperature cycle gave |z| up to 5 under the
  // null), and the test could only find an effect of the channel's spectrum where the channel has
  // none.
  auto shared_fraction = [&](const std::vector<double>& sx, const std::vector<double>& py) {
    double peak = 0, in_band = 0, total = 0;
    for (size_t j = 1; j < sx.size(); ++j) peak = std::max(peak, sx[j]);
    for (size_t j = 1; j < std::min(sx.size(), py.size()); ++j) {
      total += py[j];
      if (sx[j] >= 0.25 * peak) in_band += py[j];
    }
    return total > 0 ? in_band / total : 0.0;
  };
  auto effective_n = [&](const std::vector<double>& sx, const std::vector<double>& py) {
    double ssx = 0, spy = 0, sxy = 0;
    for (size_t j = 1; j + 1 < std::min(sx.size(), py.size()); ++j) {
      ssx += sx[j];
      spy += py[j];
      sxy += sx[j] * py[j];
    }
    return sxy > 0 ? std::min(2.0 * ssx * spy / sxy, static_cast<double>(num_decimated)) : nan;
  };
  for (const PreparedAux& prepared : aux) {
    const Eigen::VectorXd channel_blocks =
        BlockMeans(prepared.channel->values, decimation).head(num_decimated);
    const Eigen::VectorXd derivative_blocks =
        BlockMeans(prepared.derivative, decimation).head(num_decimated);
    const std::vector<double> channel_psd = Periodogram(channel_blocks, decimated_rate_hz, 1).psd,
                              derivative_psd =
                                  Periodogram(derivative_blocks, decimated_rate_hz, 1).psd;
    std::vector<double> correlation, correlation_derivative, z_channel, z_derivative, n_eff_channel,
        n_eff_derivative;
    for (int k = 0; k < num_imfs; ++k) {
      correlation.push_back(Pearson(decomposition.imfs[k], channel_blocks));
      correlation_derivative.push_back(Pearson(decomposition.imfs[k], derivative_blocks));
      const bool in_ref = view.scored[k] && k < static_cast<int>(ref.psd.size());
      // One test per (IMF, series) that shares spectrum with the IMF.
      auto add = [&](double correlation_value, const std::vector<double>& py,
                     std::vector<double>* z_out, std::vector<double>* n_eff_out) {
        double n_eff = nan, z_value = nan;
        if (in_ref && shared_fraction(ref.psd[k], py) >= options.min_shared_fraction) {
          n_eff = effective_n(ref.psd[k], py);
          z_value = correlation_value * std::sqrt(n_eff);
          if (std::isfinite(z_value)) tests.push_back({2.0 * UpperTailP(std::abs(z_value)), k});
        }
        z_out->push_back(z_value);
        n_eff_out->push_back(n_eff);
      };
      add(correlation.back(), channel_psd, &z_channel, &n_eff_channel);
      add(correlation_derivative.back(), derivative_psd, &z_derivative, &n_eff_derivative);
    }
    view.aux_names.push_back(prepared.channel->name);
    view.aux_r.push_back(correlation);
    view.aux_r_derivative.push_back(correlation_derivative);
    view.aux_z.push_back(z_channel);
    view.aux_z_derivative.push_back(z_derivative);
    view.aux_n_eff.push_back(n_eff_channel);
    view.aux_n_eff_derivative.push_back(n_eff_derivative);
  }

  // One family per record: every energy and aux test of every scored IMF, Holm's (1979) step-down
  // at `alpha` (family-wise: a correct model flags no IMF with probability >= 1 - alpha). Holm
  // rejects the r smallest p-values, p_(i) <= alpha / (m - i + 1) for i <= r; equivalently every
  // test with p <= alpha / (m - max(r, 1) + 1), the level FlagImfs quotes the critical values at.
  FlagImfs(tests, options.alpha, num_imfs, &view);
  return view;
}

}  // namespace fogpipe::model
