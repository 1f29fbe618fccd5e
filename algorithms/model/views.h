// The five views of model against measurement (`fogpipe compare`) and the dimensionless `error`.
//
// Every view reduces to standardized statistics z that are ~N(0, 1) when the model is right:
//   - Allan (domain "tau"): at octave taus, r = s2_meas / s2_model ~ chi2(nu)/nu with nu the
//     Greenhall-Riley EDF shrunk by a relative model-shape tolerance c (nu' = 2 / (2/edf + c^2));
//     z by Wilson & Hilferty (1931), two-sided. Octave spacing limits the correlation of taus.
//     Plus a targeted Gauss-Markov bump test (targeted_tests.h), whose alternative cannot hide in
//     bias_instability and white noise; alpha_v is split in two equal parts.
//   - Frequency ("frequency"): lines. The Welch PSD of the residual (Hann, 50 % overlap, segments
//     of n / welch_segments samples) over the model PSD (its shape; the level is scaled so that
//     the median ratio is the median of chi2(nu)/nu): each bin is S(f) chi2(nu)/nu under the model
//     with Welch's (1967) equivalent dof nu, so Wilson-Hilferty gives a one-sided z. The lowest
//     psd_skip_bins bins (Hann leakage) and lines slower than min_line_cycles per record are left
//     to the Allan view. The same spectrum is displayed. Failing bins are reported as bands:
//     runs of failing bins separated by gaps of at most max(band_gap_bins bins, band_gap_fraction
//     f) become one failure (FrequencyView has the reason), with its centre, peak and excess power.
//   - Time ("time"): differences of adjacent window means of the residual, at a half-window
//     stride and windows of record/time_windows x 1, 2, 4, 8, over the root mean square of the
//     same differences elsewhere in the record (leave-window-out; Student t, reported on the
//     normal scale as t c / t_c(nu)); and each window's variance against the pooled variance
//     (chi2(L-1)). The reference is the data's, not the model's: a step or a warm-up inflates the
//     fitted rate random walk (a step of size D looks like K^2 = D^2 / T), and window jumps judged
//     against that model saturate at z = sqrt(3 T / (2 L)) whatever D is. The targeted GLS step
//     and warm-up scans (targeted_tests.h) are reported here too, for ranking only (not scored).
//     A levels test (bias_levels.h) is scored with them: the segmentation of the residual into
//     constant levels, with a modified-BIC penalty per step; two or more steps fail the view,
//     with error = their -2 ln L drop over their penalty. Several jumps of the bias (or telegraph
//     switching) look like a rate random walk (or a Gauss-Markov term) to the Allan and
//     frequency views and inflate the window tests' reference; the segmentation sees them.
//   - Aux ("aux"): for each aux channel and its smoothed derivative, the score test of "rate +=
//     c * channel" under the fitted noise model, in the frequency domain (Whittle 1953): the
//     generalised least-squares t-statistic of c, with a linear trend profiled out (a random
//     walk's end-to-end leakage otherwise correlates with any slow channel; targeted_tests.h,
//     TrendDft). Records longer than 2^18 samples are tested on
//     block means (B = ceil(n / 2^18), the time view's scans too) under the noise model refitted
//     on them: a thermal effect varies over minutes, not within B / fs (0.33 s at 24 h, 100 Hz).
//     For display and the evidence sentences, Pearson r of the low-frequency residual (block means)
//     with the channel (and its derivative).
//   - IMF: diagnostic only (imf_view.h); not part of the error.
// Each view's statistic S_v = max |z| (max z for lines) is divided by its family-wise critical
// value c_v: Bonferroni at level alpha / V over the view's count (V = number of scored views).
//
//   error = max_v (S_v / c_v)^2,   consistent = error <= 1.
//
// The square makes the error a chi-square-like ratio (like a reduced chi-square, it scales with the
// energy of the misfit): error <= 1 means every view is inside its family-wise (1 - alpha) band,
// so a correct model is declared inconsistent with probability at most alpha (Bonferroni); error 9
// means the worst deviation is three times the width of that band. Under a correct model the
// error is typically 0.3-0.7. A failure is a run of statistics above c_v: a tau range, a frequency
// band, a time window, or an aux channel; severity = (max |z| / c_v)^2 over the run.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/model/spectrum.h"
#include "algorithms/model/stochastic_fit.h"

namespace fogpipe::model {

/// One aux channel sampled with the rate (input contract v1 /aux/<name>).
struct AuxChannel {
  std::string name;   ///< e.g. "temperature"
  std::string units;  ///< e.g. "degC"
  Eigen::VectorXd values;
};

struct ViewOptions {
  double alpha = 0.05;              ///< family-wise false-alarm level of `consistent`
  double relative_floor = 0.05;     ///< Allan model-shape tolerance c (closed forms are idealised)
  double max_tau_fraction = 0.125;  ///< octave taus up to record * this (EDF >= ~4)
  int welch_segments = 8;  ///< Welch segment: largest fast FFT size <= n / this (K ~ 2 x this)
  int psd_skip_bins = 4;   ///< lowest Welch bins neither tested nor displayed (Hann leakage)
  double min_line_cycles = 3.0;  ///< lines slower than this many cycles per record: Allan view
  /// Failing frequency bins closer than max(band_gap_bins bins, band_gap_fraction x frequency)
  /// are one band (one failure). Bins: a Hann window's main lobe spans 4 bins, so a pure tone
  /// fails on up to 4 adjacent bins whose chi-square scatter can leave one of them below the
  /// critical value. Fraction: a lightly damped structural mode (damping ratio zeta ~ 1-5 %) has
  /// a half-power bandwidth of 2 zeta f, 2-10 % of f; inside it single bins dip below the
  /// critical value by chi-square scatter (nu ~ 30), so gaps up to 2 % of f (zeta = 1 %) are
  /// bridged.
  int band_gap_bins = 4;
  double band_gap_fraction = 0.02;
  int time_windows = 64;  ///< finest windows of the time view: record / this
  /// Score the time view's levels test (bias_levels.h).
  bool levels_test = true;
  /// The scale of the levels test's noise ratio, s (LevelsVarianceRatio).
  double levels_batch_s = 1800.0;
  double aux_block_s = 60.0;       ///< block-mean length of the low-frequency residual
  double aux_smoothing_s = 120.0;  ///< smoothing before differentiating an aux channel
  /// Run the time view's bias-step and warm-up scans. They only name an effect (they are not
  /// scored), and only the base model's are read (compare.h ranks suggestions with them), so
  /// Compare turns them off for its trial fits.
  bool targeted_scans = true;
  bool IsValid(std::string* error) const;
};

/// Allan variance of the residual at the view's taus, from fogpipe::allan.
struct AllanData {
  std::vector<double> tau_s, avar, edf, ci_low, ci_high;  ///< avar (rad/s)^2; ci on sigma, rad/s
  std::vector<int> alpha;                 ///< noise type behind each EDF (allan/noise_id.h)
  std::vector<std::string> alpha_method;  ///< how it was identified
  allan::AllanTable table;  ///< the table itself (the IEEE terms' checks read it, compare.h)
};

/// The scored views, which are also the domains a failure lies in.
enum class ViewDomain { kTau, kFrequency, kTime, kAux };

/// "tau", "frequency", "time", "aux": the spellings `compare` writes (JSON keys and "domain"
/// values, the results file's error_<domain> attributes, the text report and the verdict).
const char* ToString(ViewDomain domain);
std::optional<ViewDomain> ParseViewDomain(std::string_view text);

struct Failure {
  ViewDomain domain = ViewDomain::kTau;
  double from = 0;  ///< s, Hz or s (NaN for aux)
  double to = 0;
  std::string channel;  ///< aux channel ("temperature" or "d(temperature)/dt"); empty otherwise
  double severity = 0;  ///< max |z| / critical over the failure (> 1)
  /// Frequency bands only (NaN / 0 otherwise): the band's excess-power-weighted centre (Hz), the
  /// frequency of its most significant bin (Hz), the largest psd / model psd in it, the excess
  /// power integral of (psd - model psd) over [from, to] ((rad/s)^2), and how many of its bins
  /// fail (the others lie in gaps the merge rule bridged, FrequencyView).
  double center_hz = std::numeric_limits<double>::quiet_NaN();
  double peak_hz = std::numeric_limits<double>::quiet_NaN();
  double peak_ratio = std::numeric_limits<double>::quiet_NaN();
  double excess_power = std::numeric_limits<double>::quiet_NaN();
  int failing_bins = 0;
};

struct AllanView {
  std::vector<double> tau_s, avar_meas, avar_model, ci_low, ci_high, edf, z;
  std::vector<int> alpha;                 ///< noise type behind each EDF (allan/noise_id.h)
  std::vector<std::string> alpha_method;  ///< how it was identified
  std::vector<std::string> term_names;
  std::vector<std::vector<double>> term_avar;  ///< per term, at tau_s
  /// Targeted Gauss-Markov bump test (targeted_tests.h): z = signed root of the chi-square drop
  /// when gauss_markov is added, its critical value, the fitted Tc (s) and sigma (rad/s); z = 0
  /// when the model already has gauss_markov.
  double gm_z = 0, gm_critical = 0, gm_correlation_time_s = 0, gm_sigma_rad_s = 0;
  /// max(max|z|, gm_z * critical / gm_critical): on the scale of the per-tau critical value.
  double statistic = 0, critical = 1;
};

struct FrequencyView {
  /// The tested Welch bins: frequency (Hz), psd and scaled model psd ((rad/s)^2/Hz).
  std::vector<double> frequency_hz, psd, model_psd;
  double dof = 2;    ///< Welch equivalent degrees of freedom of each psd value
  double scale = 1;  ///< model psd level factor (median ratio = median of chi2(dof)/dof)
  /// Significant bands (one per frequency failure): the most significant bin's frequency and z.
  std::vector<double> line_frequency_hz, line_z;
  double statistic = 0, critical = 1;
};

struct TimeView {
  double window_s = 0;
  std::vector<double> center_s, mean, variance, z_variance;  ///< per window
  /// Mean changes: boundary time, window length either side, z (octave scales, half stride;
  /// leave-window-out reference, z / critical = t / t_c(nu), see above).
  std::vector<double> boundary_s, boundary_window_s, z_mean;
  std::vector<double> change_point_s;
  /// Targeted scans (targeted_tests.h), not scored: GLS z of the best bias step and of the best
  /// warm-up under the noise model refitted without them, their critical values (the scans'
  /// look-elsewhere cost, used by the ranking), the step time (s) and size (rad/s), the warm-up
  /// time constant (s) and amplitude (rad/s).
  double step_z = 0, step_critical = 0, step_time_s = 0, step_size_rad_s = 0;
  double warmup_z = 0, warmup_critical = 0, warmup_time_constant_s = 0, warmup_amplitude_rad_s = 0;
  /// Levels test (bias_levels.h), scored: the steps the segmentation of the residual chooses
  /// (times, s), and their -2 ln L drop over their modified-BIC penalty (> 1 when chosen). Two
  /// or more steps fail the view with error levels_ratio (one step is the single-step tests').
  std::vector<double> levels_step_s;
  double levels_ratio = 0, levels_penalty = 0;  ///< levels_penalty: all steps', -2 ln L units
  double statistic = 0, critical = 1;
};

struct AuxChannelView {
  std::string name;
  std::string units;
  double r = 0, z = 0, r_derivative = 0, z_derivative = 0;
  std::vector<double> lowpass;  ///< block means of the channel
};

struct AuxView {
  std::vector<double> block_center_s, residual_lowpass;
  std::vector<AuxChannelView> channels;
  double statistic = 0, critical = 1;
};

/// One scored view's error (S_v / c_v)^2; the overall error is the largest of them.
struct ViewError {
  ViewDomain domain = ViewDomain::kTau;
  double error = 0;
};

struct Views {
  AllanView allan;
  FrequencyView frequency;
  TimeView time;
  AuxView aux;
  /// Per scored view, in the order tau, frequency, time, aux (aux only with aux channels): a
  /// term that fixes one view is credited for it even while another view dominates `error`.
  std::vector<ViewError> view_errors;
  double error = 0;
  bool consistent = true;
  std::vector<Failure> failures;
};

/// Octave averaging factors m = 1, 2, 4, ... with m / fs <= record * max_tau_fraction.
std::vector<long long> ViewAveragingFactors(long n, const ViewOptions& options);

/// Allan variance of the residual at ViewAveragingFactors, with EDF (fogpipe::allan).
AllanData ResidualAllan(const Eigen::VectorXd& residual, double sample_rate_hz,
                        const ViewOptions& options);

/// An aux channel prepared once per recording (smoothed derivative, DFTs of both), shared by the
/// base model and every trial fit.
struct PreparedAux {
  const AuxChannel* channel = nullptr;
  Eigen::VectorXd derivative;  ///< smoothed d/dt, units/s
  /// DFTs of the channel and of its derivative as the aux score sees them: of their means over
  /// blocks of ceil(n / 2^18) samples (the samples themselves on records up to 2^18 samples).
  std::vector<std::complex<double>> dft, dft_derivative;
};

/// Prepares the aux channels that have the rate's length n (others are skipped).
std::vector<PreparedAux> PrepareAux(const std::vector<AuxChannel>& aux, long n,
                                    double sample_rate_hz, const ViewOptions& options);

/// Computes the four scored views, the error, consistency and failures.
Views ComputeViews(const Eigen::VectorXd& residual, double sample_rate_hz,
                   const std::vector<PreparedAux>& aux, const StochasticModel& model,
                   const AllanData& allan, const ViewOptions& options);

/// The number of scored views: tau, frequency and time, and aux when the recording has a channel.
/// Each view is tested at alpha / this (Bonferroni over the views).
int ScoredViewCount(bool has_aux);

/// The Welch PSD the frequency view tests (Hann segments of the largest fast FFT size <= n /
/// welch_segments, 50 % overlap); empty when that segment would be shorter than 64 samples.
Spectrum FrequencyViewPsd(const Eigen::VectorXd& residual, double sample_rate_hz,
                          const ViewOptions& options);

/// The first Welch bin the frequency view tests and displays (the lower ones carry Hann leakage).
int FirstTestedBin(const ViewOptions& options);

/// The frequency view alone (as ComputeViews computes it with `num_views` scored views): its
/// failing bands, e.g. to start a narrow_band fit from.
std::vector<Failure> FrequencyFailuresOf(const Eigen::VectorXd& residual, double sample_rate_hz,
                                         const StochasticModel& model, const ViewOptions& options,
                                         int num_views);

/// The error of the view `domain` (0 when it is not scored).
double ViewErrorOf(const Views& views, ViewDomain domain);

/// The scored views whose error exceeds 1 (they fail), in view order.
std::vector<ViewDomain> FailingViews(const Views& views);

/// Means of consecutive blocks of `block` samples (a trailing partial block is dropped).
Eigen::VectorXd BlockMeans(const Eigen::VectorXd& x, long block);

/// Pearson r and Bretherton n_eff of two equally long series.
void CorrelationWithEffectiveDof(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                 double* correlation, double* n_eff);

}  // namespace fogpipe::model
