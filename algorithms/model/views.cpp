#include "algorithms/model/views.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>

#include "algorithms/allan/allan.h"
#include "algorithms/model/bias_levels.h"
#include "algorithms/model/deterministic_fit.h"
#include "algorithms/model/spectrum.h"
#include "algorithms/model/targeted_tests.h"

namespace fogpipe::model {
namespace {

Eigen::VectorXd PrefixSum(const Eigen::VectorXd& x) {
  Eigen::VectorXd sums(x.size() + 1);
  sums[0] = 0;
  for (long i = 0; i < x.size(); ++i) sums[i + 1] = sums[i] + x[i];
  return sums;
}

// Runs of consecutive indices with value > limit: [first, last] pairs.
std::vector<std::pair<int, int>> Runs(const std::vector<double>& v, double limit) {
  std::vector<std::pair<int, int>> runs;
  int start = -1;
  for (int i = 0; i <= static_cast<int>(v.size()); ++i) {
    const bool in = i < static_cast<int>(v.size()) && v[i] > limit;
    if (in && start < 0) start = i;
    if (!in && start >= 0) {
      runs.emplace_back(start, i - 1);
      start = -1;
    }
  }
  return runs;
}

// The targeted scans of the time view and the aux score run on at most this many (block-mean)
// samples.
constexpr long kScanSamples = 1L << 18;

long ScanBlock(long n) { return std::max(1L, (n + kScanSamples - 1) / kScanSamples); }

// The residual as the time view's targeted scans and the aux score see it: on long records the
// means of blocks of B = ceil(n / kScanSamples) samples (a trailing partial block is dropped), so
// that their DFTs cost O(kScanSamples log kScanSamples) instead of O(n log n) per evaluation. A
// step or a warm-up of at least 5 s, and a temperature cycle of minutes to hours, are unchanged
// by averaging over B / fs <= 1 s (24 h at 100 Hz: B = 33, 0.33 s).
struct Decimated {
  long block = 1;
  double sample_rate_hz = 0;
  Eigen::VectorXd x;
  std::vector<std::complex<double>> dft;  // MeanRemovedDft(x)
};

Decimated Decimate(const Eigen::VectorXd& residual, double fs) {
  Decimated decimated;
  decimated.block = ScanBlock(residual.size());
  decimated.sample_rate_hz = fs / static_cast<double>(decimated.block);
  decimated.x = decimated.block > 1 ? BlockMeans(residual, decimated.block) : residual;
  decimated.dft = MeanRemovedDft(decimated.x);
  return decimated;
}

// Boundaries whose leave-window-out reference has fewer degrees of freedom are not tested.
constexpr double kMinDof = 8.0;

double MaxAbs(const std::vector<double>& values, int first, int last) {
  double largest = 0;
  for (int i = first; i <= last; ++i) largest = std::max(largest, std::abs(values[i]));
  return largest;
}

std::vector<double> Abs(const std::vector<double>& values) {
  std::vector<double> magnitudes(values.size());
  for (size_t i = 0; i < values.size(); ++i) magnitudes[i] = std::abs(values[i]);
  return magnitudes;
}

// Each view is computed in two steps: the statistic step fills the view with its numbers (the
// standardized statistics, their critical value and the view's statistic), the failure step judges
// them against the critical value and reports the failures.

// Statistic step of the Allan view; `gauss_markov` receives the bump test (its tau range is where
// a failure of it shows).
void AllanStatistics(const AllanData& allan, const StochasticModel& model,
                     const ViewOptions& options, double fs, double record_s, double alpha_view,
                     AllanView* view, TargetedTest* gauss_markov) {
  const double tolerance_squared = options.relative_floor * options.relative_floor;
  view->tau_s = allan.tau_s;
  view->avar_meas = allan.avar;
  view->edf = allan.edf;
  view->alpha = allan.alpha;
  view->alpha_method = allan.alpha_method;
  view->ci_low = allan.ci_low;
  view->ci_high = allan.ci_high;
  for (Term term : model.terms) {
    view->term_names.push_back(ToString(term));
    std::vector<double> curve;
    for (double tau : allan.tau_s) curve.push_back(TermAllanVariance(model, term, tau));
    view->term_avar.push_back(curve);
  }
  for (size_t k = 0; k < allan.tau_s.size(); ++k) {
    const double model_avar = ModelAllanVariance(model, allan.tau_s[k]);
    view->avar_model.push_back(model_avar);
    const double edf = std::isfinite(allan.edf[k]) && allan.edf[k] > 0 ? allan.edf[k] : 1.0;
    const double nu = 2.0 / (2.0 / edf + tolerance_squared);
    view->z.push_back(model_avar > 0 ? WilsonHilfertyZ(allan.avar[k] / model_avar, nu) : 0.0);
  }
  // alpha_view is split between the per-tau tests and the Gauss-Markov bump test.
  view->critical = BonferroniCriticalZ(static_cast<int>(view->z.size()), 0.5 * alpha_view);
  const std::vector<double> abs_z = Abs(view->z);
  view->statistic = abs_z.empty() ? 0.0 : *std::max_element(abs_z.begin(), abs_z.end());
  *gauss_markov = ScanGaussMarkov(allan, fs, record_s, model, options, 0.5 * alpha_view);
  if (!gauss_markov->evaluated) return;
  view->gm_z = gauss_markov->z;
  view->gm_critical = gauss_markov->critical;
  view->gm_correlation_time_s = gauss_markov->location;
  view->gm_sigma_rad_s = gauss_markov->size;
  view->statistic =
      std::max(view->statistic, gauss_markov->z * view->critical / gauss_markov->critical);
}

// Failure step of the Allan view: runs of taus beyond the critical value, and the bump.
void AllanFailures(const AllanView& view, const TargetedTest& gauss_markov,
                   std::vector<Failure>* failures) {
  const std::vector<double> abs_z = Abs(view.z);
  for (auto [first, last] : Runs(abs_z, view.critical)) {
    failures->push_back({ViewDomain::kTau, view.tau_s[first] / std::sqrt(2.0),
                         view.tau_s[last] * std::sqrt(2.0), "",
                         std::pow(MaxAbs(abs_z, first, last) / view.critical, 2)});
  }
  if (gauss_markov.evaluated && gauss_markov.z > gauss_markov.critical)
    failures->push_back({ViewDomain::kTau, gauss_markov.from, gauss_markov.to, "",
                         std::pow(gauss_markov.z / gauss_markov.critical, 2)});
}

// The tested bins' z (one-sided) and the Welch bin width: what the frequency view's failure step
// judges.
struct FrequencyBins {
  std::vector<double> z;
  double bin_width_hz = 0;
};

// Statistic step of the frequency view.
FrequencyBins FrequencyStatistics(const Eigen::VectorXd& residual, double fs,
                                  const StochasticModel& model, const ViewOptions& options,
                                  double alpha_view, FrequencyView* view) {
  FrequencyBins bins;
  // One Welch PSD (Welch 1967) is both displayed and tested: Hann segments of the largest fast
  // FFT size <= n / welch_segments, 50 % overlap. Under the model each bin is S(f) chi2(nu)/nu
  // with Welch's equivalent dof nu (Percival & Walden 1993, sec. 6.17), so the ratio psd / model
  // gives a one-sided Wilson-Hilferty z. Segments of ~1 M samples keep every FFT in cache: on
  // 24 h at 100 Hz this costs ~0.5 s of CPU against 1.3 s for the 2x zero-padded periodogram (and
  // 8.6e6 bins of per-bin work it replaced). Sensitivity:
  // a line of amplitude W adds L W^2 / (6 sigma^2) to the ratio of its bin (Hann, white noise of
  // variance sigma^2, L samples per segment), averaged over K ~ 2 n / L segments. At n / L = 8
  // (K = 15, nu = 28.5) on 24 h at 100 Hz the bin is flagged at ratio 3.2 (z_c = 5.47 over 5.4e5
  // bins), i.e. W^2 = 106 sigma^2 / n, against 75 sigma^2 / n for the 2x padded periodogram
  // (ratio 19.7 over 4.3e6 bins): 1.4x the power, 1.2x the amplitude.
  const Spectrum welch = FrequencyViewPsd(residual, fs, options);
  if (welch.psd.size() < 3) return bins;
  view->dof = welch.dof;
  const double record_s = residual.size() / fs;
  std::vector<double> ratios, model_psd;
  for (int k = FirstTestedBin(options); k + 1 < static_cast<int>(welch.psd.size()); ++k) {
    if (welch.frequency_hz[k] * record_s < options.min_line_cycles) continue;
    const double model_psd_k = ModelOneSidedPsd(model, welch.frequency_hz[k], fs);
    view->frequency_hz.push_back(welch.frequency_hz[k]);
    view->psd.push_back(welch.psd[k]);
    model_psd.push_back(model_psd_k);
    ratios.push_back(model_psd_k > 0 ? welch.psd[k] / model_psd_k : 0.0);
  }
  if (ratios.empty()) return bins;
  std::vector<double> sorted_ratios = ratios;
  std::nth_element(sorted_ratios.begin(), sorted_ratios.begin() + sorted_ratios.size() / 2,
                   sorted_ratios.end());
  // Only the shape of the model PSD is tested here (its level is the Allan view's business):
  // scale it so that the median ratio is the median of chi2(nu)/nu.
  view->scale = sorted_ratios[sorted_ratios.size() / 2] / ChiSquareMedianOverNu(welch.dof);
  if (!(view->scale > 0)) view->scale = 1.0;
  view->model_psd.resize(model_psd.size());
  for (size_t i = 0; i < model_psd.size(); ++i) view->model_psd[i] = view->scale * model_psd[i];
  std::vector<double>& z = bins.z;
  z.resize(ratios.size());
  for (size_t i = 0; i < ratios.size(); ++i)
    z[i] = WilsonHilfertyZ(ratios[i] / view->scale, welch.dof);
  // Bins are tested one-sided (a line raises its bin); adjacent Hann bins are correlated, which
  // makes Bonferroni over every tested bin conservative.
  view->critical = BonferroniCriticalZOneSided(static_cast<int>(z.size()), alpha_view);
  view->statistic = *std::max_element(z.begin(), z.end());
  bins.bin_width_hz = welch.frequency_hz[1];
  return bins;
}

// Failure step of the frequency view: failing bands, and each band's line in the view.
void FrequencyFailures(const FrequencyBins& bins, const ViewOptions& options, FrequencyView* view,
                       std::vector<Failure>* failures) {
  const std::vector<double>& z = bins.z;
  const double bin_width_hz = bins.bin_width_hz;
  const std::vector<double>& freq = view->frequency_hz;
  // Runs of failing bins, merged into bands across gaps of at most max(band_gap_bins bins,
  // band_gap_fraction f) (ViewOptions has the reason): a vibration band or a line's leakage is one
  // failure, not one per bin.
  std::vector<std::pair<int, int>> bands;
  for (auto run : Runs(z, view->critical)) {
    if (!bands.empty()) {
      const double gap = freq[run.first] - freq[bands.back().second];
      if (gap <= std::max(options.band_gap_bins * bin_width_hz,
                          options.band_gap_fraction * freq[run.first])) {
        bands.back().second = run.second;
        continue;
      }
    }
    bands.push_back(run);
  }
  for (auto [first, last] : bands) {
    Failure failure{ViewDomain::kFrequency, freq[first] - bin_width_hz, freq[last] + bin_width_hz,
                    "", 0.0};
    int peak = first;
    double excess = 0, positive = 0, moment = 0, peak_ratio = 0;
    for (int i = first; i <= last; ++i) {
      if (z[i] > z[peak]) peak = i;
      if (z[i] > view->critical) ++failure.failing_bins;
      const double excess_density = view->psd[i] - view->model_psd[i];
      excess += excess_density * bin_width_hz;
      positive += std::max(excess_density, 0.0);
      moment += std::max(excess_density, 0.0) * freq[i];
      peak_ratio =
          std::max(peak_ratio, view->model_psd[i] > 0 ? view->psd[i] / view->model_psd[i] : 0.0);
    }
    failure.severity = std::pow(z[peak] / view->critical, 2);
    failure.center_hz = positive > 0 ? moment / positive : freq[peak];
    failure.peak_hz = freq[peak];
    failure.peak_ratio = peak_ratio;
    failure.excess_power = excess;
    view->line_frequency_hz.push_back(freq[peak]);
    view->line_z.push_back(z[peak]);
    failures->push_back(failure);
  }
}

// Statistic step of the time view, with the targeted scans (not scored).
void TimeStatistics(const Eigen::VectorXd& residual, double fs, const Decimated& decimated,
                    const StochasticModel& model, const ViewOptions& options, double alpha_view,
                    TimeView* view) {
  const long n = residual.size();
  const long window_length = std::max(16L, n / options.time_windows);
  view->window_s = window_length / fs;
  const Eigen::VectorXd prefix_sums = PrefixSum(residual);
  // Windowed mean and variance (finest scale).
  const long num_windows = n / window_length;
  std::vector<double> variances;
  for (long window = 0; window < num_windows; ++window) {
    const auto segment = residual.segment(window * window_length, window_length);
    const double window_mean = segment.mean();
    view->center_s.push_back((window * window_length + 0.5 * window_length) / fs);
    view->mean.push_back(window_mean);
    variances.push_back((segment.array() - window_mean).square().sum() / (window_length - 1));
  }
  view->variance = variances;
  double pooled = 0;
  for (double variance : variances) pooled += variance;
  pooled /= std::max<size_t>(variances.size(), 1);
  for (double variance : variances)
    view->z_variance.push_back(WilsonHilfertyZ(variance / pooled, window_length - 1.0));
  // Mean changes at octave scales l = 1, 2, 4, 8 window lengths: a step is best seen by windows
  // about as long as the noise allows (white noise favours long windows, rate random walk short
  // ones). Reference: the mean square of the same differences elsewhere in the record (boundaries
  // at least 2 l away, whose windows do not overlap this one), not the fitted model: a step or a
  // warm-up inflates the fitted rate_random_walk / rate_ramp (K^2 = D^2 / T for a step), which
  // would cap z at sqrt(3 T / (2 l)) whatever the step size; a single event cannot inflate the
  // leave-window-out reference. Any noise with stationary increments (white, flicker, random
  // walk) gives homogeneous differences, so the reference is right whatever the noise model. The
  // ratio t is Student t with nu = m / 1.75 (m differences at half-window stride; for white
  // noise their correlations at lags l/2, l, 3l/2 are 1/4, -1/2, -1/4, so var(mean d^2) is 1.75
  // times that of m independent squares). It is judged against the Student critical value
  // t_c(nu) of the same family-wise level (Wallace 1959) and reported on the normal scale as
  // z = t c / t_c(nu), so that z / c = t / t_c: the error still grows with the energy of the
  // jump. Boundaries with nu < kMinDof are not tested.
  std::vector<double> t_mean, nu_mean;
  for (long scale = window_length; scale <= 8 * window_length && 2 * scale <= n; scale *= 2) {
    const long stride = std::max(1L, scale / 2);
    std::vector<double> differences, boundary_samples;
    for (long boundary = scale; boundary + scale <= n; boundary += stride) {
      differences.push_back((prefix_sums[boundary + scale] - prefix_sums[boundary]) / scale -
                            (prefix_sums[boundary] - prefix_sums[boundary - scale]) / scale);
      boundary_samples.push_back(static_cast<double>(boundary));
    }
    const long num_differences = static_cast<long>(differences.size());
    std::vector<double> squares_prefix(num_differences + 1, 0.0);  // prefix sums of d^2
    for (long i = 0; i < num_differences; ++i)
      squares_prefix[i + 1] = squares_prefix[i] + differences[i] * differences[i];
    const long near = (2 * scale + stride - 1) / stride - 1;  // |j - i| <= near: windows overlap
    for (long i = 0; i < num_differences; ++i) {
      const long lo = std::max(0L, i - near), hi = std::min(num_differences - 1, i + near);
      const long others = num_differences - (hi - lo + 1);
      const double nu = others / 1.75;
      if (nu < kMinDof) continue;
      const double reference_mean_square =
          (squares_prefix[num_differences] - (squares_prefix[hi + 1] - squares_prefix[lo])) /
          others;
      view->boundary_s.push_back(boundary_samples[i] / fs);
      view->boundary_window_s.push_back(scale / fs);
      t_mean.push_back(reference_mean_square > 0 ? differences[i] / std::sqrt(reference_mean_square)
                                                 : 0.0);
      nu_mean.push_back(nu);
    }
  }
  const int count = static_cast<int>(t_mean.size() + view->z_variance.size());
  view->critical = BonferroniCriticalZ(count, alpha_view);
  // Levels test (bias_levels.h): on the view's scale, z = c sqrt(ratio), so (z / c)^2 = ratio.
  if (options.levels_test) {
    // Under the fitted noise model's correlation at the segments' scale (bias_levels.h), without
    // rate random walk and rate ramp: they are what several levels inflate (K^2 = sum D^2 / T).
    StochasticModel correlated = model;
    correlated.k_rad_s_sqrt_s = 0;
    correlated.r_rad_s2 = 0;
    LevelsOptions levels_options;
    levels_options.max_design_bytes = 0;  // a test: no design is built here
    levels_options.variance_ratio =
        LevelsVarianceRatio([&](double tau) { return ModelAllanVariance(correlated, tau); },
                            levels_options.block_s, options.levels_batch_s);
    const LevelsSegmentation levels = SegmentLevels(residual, fs, levels_options);
    for (long index : levels.step_index) view->levels_step_s.push_back(index / fs);
    if (levels.step_index.size() >= 2) {
      view->levels_penalty = levels.penalty * static_cast<double>(levels.step_index.size());
      view->levels_ratio = levels.gain / view->levels_penalty;
      view->statistic = std::max(view->statistic, view->critical * std::sqrt(view->levels_ratio));
    }
  }
  for (size_t i = 0; i < t_mean.size(); ++i)
    view->z_mean.push_back(t_mean[i] * view->critical /
                           NormalToStudent(view->critical, nu_mean[i]));
  const std::vector<double> abs_z_mean = Abs(view->z_mean), abs_z_variance = Abs(view->z_variance);
  for (double magnitude : abs_z_mean) view->statistic = std::max(view->statistic, magnitude);
  for (double magnitude : abs_z_variance) view->statistic = std::max(view->statistic, magnitude);
  // The targeted GLS scans name the effect (they rank bias_step against warmup, compare.h); they
  // are not scored: their null depends on the fitted low-frequency noise, which a 6 h record
  // determines poorly (rate random walk is often fitted at 0), while the window tests above are
  // self-normalised.
  // On long records the scans run on block means (Decimated, below); the noise model is refitted
  // on the block means themselves.
  if (!options.targeted_scans) return;
  const TargetedTest step = ScanBiasStep(decimated.x, decimated.sample_rate_hz, decimated.dft,
                                         model, options, alpha_view, view->window_s);
  if (step.evaluated) {
    view->step_z = step.z;
    view->step_critical = step.critical;
    view->step_time_s = step.location;
    view->step_size_rad_s = step.size;
  }
  const TargetedTest warmup =
      ScanWarmup(decimated.x, decimated.sample_rate_hz, decimated.dft, model, options, alpha_view);
  if (warmup.evaluated) {
    view->warmup_z = warmup.z;
    view->warmup_critical = warmup.critical;
    view->warmup_time_constant_s = warmup.location;
    view->warmup_amplitude_rad_s = warmup.size;
  }
}

// Failure step of the time view: failing boundaries (merged into intervals, whose peaks are the
// change points) and runs of failing window variances. `record_s` bounds the intervals.
void TimeFailures(double record_s, TimeView* view, std::vector<Failure>* failures) {
  const std::vector<double> abs_z_mean = Abs(view->z_mean), abs_z_variance = Abs(view->z_variance);
  // Failing boundaries -> intervals [b - l, b + l], merged across scales.
  struct Interval {
    double from, to, peak_z, peak_s;
  };
  std::vector<Interval> intervals;
  for (size_t i = 0; i < abs_z_mean.size(); ++i) {
    if (abs_z_mean[i] <= view->critical) continue;
    intervals.push_back({std::max(0.0, view->boundary_s[i] - view->boundary_window_s[i]),
                         std::min(record_s, view->boundary_s[i] + view->boundary_window_s[i]),
                         abs_z_mean[i], view->boundary_s[i]});
  }
  std::sort(intervals.begin(), intervals.end(),
            [](const auto& lhs, const auto& rhs) { return lhs.from < rhs.from; });
  std::vector<Interval> merged;
  for (const auto& interval : intervals) {
    if (!merged.empty() && interval.from <= merged.back().to) {
      auto& merged_last = merged.back();
      merged_last.to = std::max(merged_last.to, interval.to);
      if (interval.peak_z > merged_last.peak_z) {
        merged_last.peak_z = interval.peak_z;
        merged_last.peak_s = interval.peak_s;
      }
    } else {
      merged.push_back(interval);
    }
  }
  for (const auto& interval : merged) {
    view->change_point_s.push_back(interval.peak_s);
    failures->push_back({ViewDomain::kTime, interval.from, interval.to, "",
                         std::pow(interval.peak_z / view->critical, 2)});
  }
  // Several levels: the span of their steps.
  if (view->levels_ratio > 1.0)
    failures->push_back({ViewDomain::kTime, view->levels_step_s.front(), view->levels_step_s.back(),
                         "", view->levels_ratio});
  for (auto [first, last] : Runs(abs_z_variance, view->critical)) {
    failures->push_back({ViewDomain::kTime, view->center_s[first] - 0.5 * view->window_s,
                         view->center_s[last] + 0.5 * view->window_s, "",
                         std::pow(MaxAbs(abs_z_variance, first, last) / view->critical, 2)});
  }
}

// Statistic step of the aux view.
void AuxStatistics(const Eigen::VectorXd& residual, double fs, const Decimated& decimated,
                   const std::vector<PreparedAux>& aux, const StochasticModel& model,
                   const ViewOptions& options, double alpha_view, AuxView* view) {
  const long block = std::max(1L, static_cast<long>(std::lround(options.aux_block_s * fs)));
  const Eigen::VectorXd residual_lowpass = BlockMeans(residual, block);
  if (residual_lowpass.size() < 8) return;
  for (long block_index = 0; block_index < residual_lowpass.size(); ++block_index) {
    view->block_center_s.push_back((block_index * block + 0.5 * block) / fs);
    view->residual_lowpass.push_back(residual_lowpass[block_index]);
  }
  // The score test runs on the block means (all samples when block = 1) under the noise model
  // refitted on them: the channels' DFTs (PrepareAux) are of their block means over the same
  // blocks.
  const StochasticModel block_model =
      decimated.block > 1 ? RefitNoise(decimated.x, decimated.sample_rate_hz, model, options)
                          : model;
  const std::vector<double> whittle_weights =
      WhittleWeights(block_model, decimated.x.size(), decimated.sample_rate_hz);
  // A linear trend is profiled out of each score (TrendDft: a random walk's end-to-end leakage
  // would otherwise correlate with any slow channel).
  const std::vector<std::complex<double>> trend = TrendDft(decimated.x.size());
  for (const PreparedAux& prepared : aux) {
    const AuxChannel& channel = *prepared.channel;
    AuxChannelView channel_view;
    channel_view.name = channel.name;
    channel_view.units = channel.units;
    const Eigen::VectorXd channel_lowpass = BlockMeans(channel.values, block),
                          derivative_lowpass = BlockMeans(prepared.derivative, block);
    channel_view.lowpass.assign(channel_lowpass.data(),
                                channel_lowpass.data() + channel_lowpass.size());
    double unused_n_eff = 0;
    CorrelationWithEffectiveDof(residual_lowpass, channel_lowpass, &channel_view.r, &unused_n_eff);
    CorrelationWithEffectiveDof(residual_lowpass, derivative_lowpass, &channel_view.r_derivative,
                                &unused_n_eff);
    channel_view.z = WhittleScoreZ(decimated.dft, prepared.dft, whittle_weights, &trend);
    channel_view.z_derivative =
        WhittleScoreZ(decimated.dft, prepared.dft_derivative, whittle_weights, &trend);
    view->channels.push_back(channel_view);
  }
  view->critical = BonferroniCriticalZ(
      2 * static_cast<int>(std::max<size_t>(view->channels.size(), 1)), alpha_view);
  for (const auto& channel_view : view->channels)
    view->statistic =
        std::max({view->statistic, std::abs(channel_view.z), std::abs(channel_view.z_derivative)});
}

// Failure step of the aux view: each channel and derivative beyond the critical value.
void AuxFailures(const AuxView& view, std::vector<Failure>* failures) {
  for (const auto& channel_view : view.channels) {
    const double nan = std::nan("");
    if (std::abs(channel_view.z) > view.critical)
      failures->push_back({ViewDomain::kAux, nan, nan, channel_view.name,
                           std::pow(channel_view.z / view.critical, 2)});
    if (std::abs(channel_view.z_derivative) > view.critical)
      failures->push_back({ViewDomain::kAux, nan, nan, "d(" + channel_view.name + ")/dt",
                           std::pow(channel_view.z_derivative / view.critical, 2)});
  }
}

}  // namespace

const char* ToString(ViewDomain domain) {
  switch (domain) {
    case ViewDomain::kTau:
      return "tau";
    case ViewDomain::kFrequency:
      return "frequency";
    case ViewDomain::kTime:
      return "time";
    case ViewDomain::kAux:
      return "aux";
  }
  return "tau";
}

std::optional<ViewDomain> ParseViewDomain(std::string_view text) {
  for (ViewDomain domain :
       {ViewDomain::kTau, ViewDomain::kFrequency, ViewDomain::kTime, ViewDomain::kAux})
    if (text == ToString(domain)) return domain;
  return std::nullopt;
}

bool ViewOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* message) {
    if (error) *error = message;
    return false;
  };
  if (!(alpha > 0 && alpha < 1)) return fail("alpha must be in (0, 1)");
  if (!(relative_floor >= 0 && relative_floor < 1)) return fail("relative_floor in [0, 1)");
  if (!(max_tau_fraction > 0 && max_tau_fraction <= 0.5))
    return fail("max_tau_fraction in (0, 0.5]");
  if (!(levels_batch_s > 0)) return fail("levels_batch_s must be > 0");
  if (welch_segments < 1 || psd_skip_bins < 1 || time_windows < 4)
    return fail("welch_segments >= 1, psd_skip_bins >= 1, time_windows >= 4");
  if (band_gap_bins < 0 || !(band_gap_fraction >= 0 && band_gap_fraction < 1))
    return fail("band_gap_bins >= 0, band_gap_fraction in [0, 1)");
  if (!(aux_block_s > 0 && aux_smoothing_s >= 0))
    return fail("aux_block_s > 0, aux_smoothing_s >= 0");
  return true;
}

Eigen::VectorXd BlockMeans(const Eigen::VectorXd& x, long block) {
  const long num_blocks = x.size() / block;
  Eigen::VectorXd means(num_blocks);
  for (long block_index = 0; block_index < num_blocks; ++block_index)
    means[block_index] = x.segment(block_index * block, block).mean();
  return means;
}

std::vector<long long> ViewAveragingFactors(long n, const ViewOptions& options) {
  std::vector<long long> factors;
  for (long long factor = 1; factor <= static_cast<long long>(n * options.max_tau_fraction);
       factor *= 2)
    factors.push_back(factor);
  return factors;
}

AllanData ResidualAllan(const Eigen::VectorXd& residual, double fs, const ViewOptions& options) {
  allan::AllanOptions allan_options;
  allan_options.grid.kind = allan::TauGridKind::kExplicit;
  allan_options.grid.explicit_m = ViewAveragingFactors(residual.size(), options);
  const allan::AllanResult result = allan::ComputeAllan(residual, fs, allan_options);
  AllanData data;
  const auto& table = result.table;
  for (size_t i = 0; i < table.size(); ++i) {
    data.tau_s.push_back(table.tau_s[i]);
    data.avar.push_back(table.sigma[i] * table.sigma[i]);
    data.edf.push_back(table.edf[i]);
    data.alpha.push_back(table.alpha[i]);
    data.alpha_method.push_back(allan::ToString(table.alpha_method[i]));
    data.ci_low.push_back(table.ci_low[i]);
    data.ci_high.push_back(table.ci_high[i]);
  }
  data.table = table;
  return data;
}

void CorrelationWithEffectiveDof(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                 double* correlation, double* n_eff) {
  const long n = a.size();
  const Eigen::VectorXd x = a.array() - a.mean(), y = b.array() - b.mean();
  const double sxx = x.squaredNorm(), syy = y.squaredNorm();
  *correlation = (sxx > 0 && syy > 0) ? x.dot(y) / std::sqrt(sxx * syy) : 0.0;
  // Bretherton et al. (1999) eq. 31: n_eff = n / (1 + 2 sum_k (1 - k/n) rho_x(k) rho_y(k)).
  double sum = 0;
  const long max_lag = n / 5;
  for (long lag = 1; lag <= max_lag && sxx > 0 && syy > 0; ++lag) {
    const double autocorrelation_x = x.head(n - lag).dot(x.tail(n - lag)) / sxx;
    const double autocorrelation_y = y.head(n - lag).dot(y.tail(n - lag)) / syy;
    sum += (1.0 - static_cast<double>(lag) / n) * autocorrelation_x * autocorrelation_y;
  }
  *n_eff = std::clamp(n / (1.0 + 2.0 * sum), 4.0, static_cast<double>(n));
}

std::vector<PreparedAux> PrepareAux(const std::vector<AuxChannel>& aux, long n, double fs,
                                    const ViewOptions& options) {
  std::vector<PreparedAux> out;
  for (const AuxChannel& channel : aux) {
    if (channel.values.size() != n) continue;
    PreparedAux prepared;
    prepared.channel = &channel;
    prepared.derivative = SmoothedDerivative(channel.values, fs, options.aux_smoothing_s);
    const long block = ScanBlock(n);
    prepared.dft = MeanRemovedDft(block > 1 ? BlockMeans(channel.values, block) : channel.values);
    prepared.dft_derivative =
        MeanRemovedDft(block > 1 ? BlockMeans(prepared.derivative, block) : prepared.derivative);
    out.push_back(std::move(prepared));
  }
  return out;
}

Views ComputeViews(const Eigen::VectorXd& residual, double fs, const std::vector<PreparedAux>& aux,
                   const StochasticModel& model, const AllanData& allan,
                   const ViewOptions& options) {
  Views views;
  const bool has_aux = !aux.empty();
  const int num_views = ScoredViewCount(has_aux);
  const double alpha_view = options.alpha / num_views;
  const Decimated decimated = Decimate(residual, fs);
  const double record_s = residual.size() / fs;
  TargetedTest gauss_markov;
  AllanStatistics(allan, model, options, fs, record_s, alpha_view, &views.allan, &gauss_markov);
  AllanFailures(views.allan, gauss_markov, &views.failures);
  const FrequencyBins bins =
      FrequencyStatistics(residual, fs, model, options, alpha_view, &views.frequency);
  FrequencyFailures(bins, options, &views.frequency, &views.failures);
  TimeStatistics(residual, fs, decimated, model, options, alpha_view, &views.time);
  TimeFailures(record_s, &views.time, &views.failures);
  if (has_aux) {
    AuxStatistics(residual, fs, decimated, aux, model, options, alpha_view, &views.aux);
    AuxFailures(views.aux, &views.failures);
  }
  auto sq = [](double x) { return x * x; };
  views.view_errors = {
      {ViewDomain::kTau, sq(views.allan.statistic / views.allan.critical)},
      {ViewDomain::kFrequency, sq(views.frequency.statistic / views.frequency.critical)},
      {ViewDomain::kTime, sq(views.time.statistic / views.time.critical)}};
  if (has_aux)
    views.view_errors.push_back({ViewDomain::kAux, sq(views.aux.statistic / views.aux.critical)});
  views.error = 0;
  for (const ViewError& view_error : views.view_errors)
    views.error = std::max(views.error, view_error.error);
  views.consistent = views.error <= 1.0;
  return views;
}

int ScoredViewCount(bool has_aux) { return has_aux ? 4 : 3; }

Spectrum FrequencyViewPsd(const Eigen::VectorXd& residual, double fs, const ViewOptions& options) {
  const long segment_length =
      FastFftSizeAtMost(std::max(1L, static_cast<long>(residual.size()) / options.welch_segments));
  if (segment_length < 64) return {};
  return WelchPsd(residual, fs, static_cast<int>(segment_length));
}

int FirstTestedBin(const ViewOptions& options) { return std::max(1, options.psd_skip_bins); }

std::vector<Failure> FrequencyFailuresOf(const Eigen::VectorXd& residual, double fs,
                                         const StochasticModel& model, const ViewOptions& options,
                                         int num_views) {
  FrequencyView view;
  std::vector<Failure> failures;
  const FrequencyBins bins =
      FrequencyStatistics(residual, fs, model, options, options.alpha / num_views, &view);
  if (!bins.z.empty()) FrequencyFailures(bins, options, &view, &failures);
  return failures;
}

double ViewErrorOf(const Views& views, ViewDomain domain) {
  for (const ViewError& view_error : views.view_errors)
    if (view_error.domain == domain) return view_error.error;
  return 0.0;
}

std::vector<ViewDomain> FailingViews(const Views& views) {
  std::vector<ViewDomain> failing;
  for (const ViewError& view_error : views.view_errors)
    if (view_error.error > 1.0) failing.push_back(view_error.domain);
  return failing;
}

}  // namespace fogpipe::model
