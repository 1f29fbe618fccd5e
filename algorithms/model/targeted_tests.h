// Targeted tests of the model comparison (`fogpipe compare`): tests of the fitted model against one
// specific alternative each, with a reference scale that the alternative cannot inflate.
//
// Why. The default model's rate_random_walk and rate_ramp are fitted on the Allan curve of the
// residual. A bias step of size D adds D^2 tau / (3 T) to sigma^2(tau), exactly the law of a rate
// random walk with K^2 = D^2 / T, so the fitted K absorbs it; window-mean jumps judged against
// that inflated K saturate at z = sqrt(3 T / (2 L)) whatever D is (sqrt(12) at L = T / 8). A
// warm-up is absorbed the same way, and a Gauss-Markov bump mostly by bias_instability (its
// plateau) and white noise (its 1/tau tail). An omnibus test against a model fitted on the
// contaminated data cannot see these; a test against the specific alternative can:
//
//  - Gauss-Markov bump (tau view, scored): the signed root of the chi-square drop of the Allan
//    fit when gauss_markov is added, z = sqrt(chi2_model - chi2_model+GM). Tc is not identified
//    under the null, so the one-sided supremum over log Tc is judged with Davies' (1987) bound
//    P(sup Z > c) <= (1 - Phi(c)) + V exp(-c^2 / 2) / (2 pi), V the arc length of the unit GM
//    score direction (weighted like the fit, projected off the model's own columns) over the
//    searched log Tc range.
//  - Bias step and warm-up (time view, NOT scored, used to rank bias_step against warmup): the
//    step is located by the CUSUM scan of the residual (Page 1954; Hinkley 1970) and the warm-up
//    time constant by the profile over [max(5 s, 3 / fs), T / 3] (both FitDeterministic), the
//    effect is removed and the noise model refitted on the Allan variance of what remains (the
//    noise under the alternative, which the effect cannot inflate). The statistic is the
//    generalised least-squares t-statistic of the effect under that model, in the frequency
//    domain (Whittle 1953). Critical values: for the step, the supremum of a standardised
//    Brownian bridge over [a, 1 - a] (a = step margin), P(sup |U| > c) ~ c phi(c) ln((1 - a)^2 /
//    a^2) + 4 phi(c) / c (James, James & Siegmund 1987; it reproduces Andrews' 1993 sup-Wald 5 %
//    value 9.84 at a = 0.05 within 0.2 in c); for the warm-up, whose regressors are smooth in log
//    tau_w (correlation 1 / cosh(Delta / 2) in white noise, lambda_2 = 1/4), Rice's (1945)
//    formula P(sup |Z| > c) ~ 2 (1 - Phi(c)) + L sqrt(lambda_2) / pi exp(-c^2 / 2) over the log
//    range L. Why not scored: their null needs the low-frequency noise right, and a 6 h record
//    often fits rate random walk at 0 when it is there (on effect-free design seeds 500-539, 8 of
//    40 exceeded the step critical value); the time view's self-normalised window tests do not
//    have that weakness. As a ranking cost, c^2 - z^2 (compare.h) they only compare the two scans
//    under the same noise model.
// The Gauss-Markov critical value was checked on effect-free simulated navigation-grade
// recordings, design seeds 500-539 (disjoint from the test seeds): none exceeded it.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "algorithms/model/stochastic_fit.h"
#include "algorithms/model/views.h"

namespace fogpipe::model {

/// The terms of `model` refitted on the Allan variance of x (its view taus; `model` itself when
/// the fit fails): the noise of x under the model's terms.
StochasticModel RefitNoise(const Eigen::VectorXd& x, double sample_rate_hz,
                           const StochasticModel& model, const ViewOptions& options);

/// DFT of x - mean(x), bins 0 .. n/2 (real input: the rest is their conjugate; RealDftHalf).
std::vector<std::complex<double>> MeanRemovedDft(const Eigen::VectorXd& x);

/// Whittle weights w_k = E|R_k|^2 = n fs S(f_k) / 2 for k = 1 .. n/2 - 1 under the one-sided model
/// PSD S (w_0 = 0: the mean is not tested).
std::vector<double> WhittleWeights(const StochasticModel& model, long n, double sample_rate_hz);

/// GLS t-statistic (Whittle score) of "x += c * regressor" given the DFTs of the series and the
/// regressor (bins 1 .. weights.size() - 1 are used). With `nuisance` (a DFT), the score of c
/// after the nuisance's coefficient is profiled out (partial GLS).
double WhittleScoreZ(const std::vector<std::complex<double>>& series_dft,
                     const std::vector<std::complex<double>>& regressor_dft,
                     const std::vector<double>& weights,
                     const std::vector<std::complex<double>>* nuisance = nullptr);

/// DFT of the linear trend t = 0 .. n - 1 at bins 0 .. n/2 (bin 0 left at 0, the mean is not
/// tested): -n / (1 - e^{-2 pi i k / n}) (summation by parts).
/// Why it is the aux score's nuisance: the DFT of a finite rate random walk carries its
/// end-to-end difference into every low bin with exactly this shape, x_{n-1} - x_0 times
/// 1 / (1 - e^{-i w_k}) (the jump at the wrap of the periodic extension), and so does that of any
/// smooth channel. The Whittle approximation, bins independent with E|R_k|^2 = w_k, ignores this
/// common term; the score of a temperature cycle against a strong random walk then scatters many
/// times its nominal sd. Profiling out a trend absorbs the common term (first differences would
/// too, but they over-difference the white noise, whose periodogram at the lowest bins is then
/// ruled by the two end samples).
std::vector<std::complex<double>> TrendDft(long n);

/// Critical value c of the two-sided supremum of a standardised Brownian bridge over
/// [margin, 1 - margin] at level alpha (James, James & Siegmund 1987 approximation).
double BridgeSupremumCritical(double alpha, double margin);

/// Critical value c of the supremum of a smooth unit-variance Gaussian process over a parameter
/// range of arc length `length` (Rice 1945, Davies 1987): solves
/// k (1 - Phi(c)) + length exp(-c^2 / 2) / (2 pi) * (two_sided ? 2 : 1) = alpha, k = 2 or 1.
double SmoothSupremumCritical(double alpha, double length, bool two_sided);

/// The result of one targeted scan.
struct TargetedTest {
  bool evaluated = false;   ///< false when the scan could not run (too short, fit failed)
  double z = 0;             ///< signed statistic (GM: >= 0)
  double critical = 0;      ///< its critical |z| at the level the caller gave
  double location = 0;      ///< step time s | warm-up time constant s | GM correlation time s
  double size = 0;          ///< step size rad/s | warm-up amplitude rad/s | GM sigma rad/s
  double from = 0, to = 0;  ///< where it shows: time window s (step, warm-up) or tau range s (GM)
};

/// Bias-step scan of a residual (see the header comment). `residual_dft` = MeanRemovedDft(r).
/// `window_s` widens the reported time window around the step (the time view's window).
TargetedTest ScanBiasStep(const Eigen::VectorXd& residual, double sample_rate_hz,
                          const std::vector<std::complex<double>>& residual_dft,
                          const StochasticModel& model, const ViewOptions& options, double alpha,
                          double window_s);

/// Warm-up scan of a residual (see the header comment).
TargetedTest ScanWarmup(const Eigen::VectorXd& residual, double sample_rate_hz,
                        const std::vector<std::complex<double>>& residual_dft,
                        const StochasticModel& model, const ViewOptions& options, double alpha);

/// Gauss-Markov bump test on the residual's Allan variance (skipped when the model has one).
TargetedTest ScanGaussMarkov(const AllanData& allan, double sample_rate_hz, double record_s,
                             const StochasticModel& model, const ViewOptions& options,
                             double alpha);

}  // namespace fogpipe::model
