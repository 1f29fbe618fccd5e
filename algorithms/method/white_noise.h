// The Kalman measurement-noise variance R (and the rule for q) of each component's filter.
//
// Rule (documented in schemas/results-v1.md as well):
//  1. The raw signal's white-noise variance is estimated from its first differences with a robust
//     scale: sigma_w^2 = (1.4826 MAD(diff x))^2 / 2. For white noise of variance s^2 the difference
//     has variance 2 s^2; slower terms (bias instability, rate random walk, ramp) barely change
//     consecutive samples, and the MAD ignores leftover gross errors.
//  2. That variance is shared among the IMFs as EMD shares white noise: EMD acts on white noise as
//     a dyadic filter bank whose IMF energies obey E_k T_k ~ constant, T_k the mean period
//     (Wu & Huang 2004, Proc. R. Soc. A 460:1597; Flandrin, Rilling & Goncalves 2004). So IMF k
//     receives the share (1/T_k) / sum_j (1/T_j) of sigma_w^2, capped at the IMF's own variance.
//     The residue (a trend) counts as one cycle over the record (T = N): a tiny share, so that
//     its filter follows it.
//
//  3. The share is band-passed noise, not white: EMD makes it predictable, so an IMF's AR
//     innovation variance sigma_e^2 is usually far below its share (measured on the real ADIS16405
//     record: imf3 sigma_e^2 = 1.5e-8 vs share 3.6e-6 (rad/s)^2, imf10 1e-27 vs 1.4e-8). Handing
//     the share itself to the filter as white R leaves no room for process noise: the moment
//     match of kalman/noise_defaults.h, H P H' + R = sigma_e^2, then clamps q to 0, the gain decays
//     to zero and the output is the AR model running free (fogpipe < 0.2; on that record method 1
//     raised the Allan deviation instead of lowering it, N 110 deg/sqrt(h) against raw 2.1). So R
//     is the white FRACTION of the component's one-step prediction error instead:
//        R_k = (share_k / var_k) sigma_e,k^2,   q_k from H P H' + R_k = sigma_e,k^2
//        (noise_defaults.h)
//     A component that is mostly signal (share << variance) gets R << sigma_e^2 and is followed;
//     one that is mostly noise gets q -> 0 and is suppressed; q/R depends on the white fraction,
//     not on how smooth the IMF is, so slow IMFs whose sigma_e^2 is 1e-20 of their variance are
//     neither frozen nor left unfiltered. A component whose share reaches its variance (the cap of
//     step 2) is judged pure noise: q = 0 and P(0|0) = 0, so its filter outputs its mean instead
//     of extrapolating its AR model from a fitted initial state.
//     Evidence (fogpipe sweep, RMS error against the true rate, simulated moving-rate records,
//     AR orders 2-8): this rule's RMS error is 2.11-2.17, 59.6-60.1 and 0.411-0.416 deg/h on three
//     records (raw: 9.5, ~300, ~1.9), nearly independent of the AR order; R = share with q by the
//     moment match gave 4.9-238, 11-4460 and 2.1-1259. See schemas/results-v1.md.
//
// Why not R = sigma_w^2 on every IMF or Q = innovation variance with R = sigma_w^2: the AR
// innovation variance of a noisy component already contains its share of the measurement noise
// (method.md, "What to keep in mind"); the full sigma_w^2 as R on every IMF would count the white
// noise once per IMF, and R = sigma_w^2 with Q = innovation variance would count it twice.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/emd/emd.h"

namespace fogpipe::method {

/// How a component's Kalman q and R follow from its white-noise share (see the header comment).
enum class ComponentNoiseRule {
  /// Step 3 below: R = (share / variance) sigma_e^2, q by innovation matching. The default.
  kShareOfInnovation,
  /// R = share, q by innovation matching (kalman::DefaultNoise) directly. Right when the white
  /// noise is white, i.e. for method 2's raw signal; on EMD components it gives q = 0 whenever
  /// the share exceeds sigma_e^2, which band-passed noise makes the common case (fogpipe < 0.2).
  kInnovationMatch,
};

const char* ToString(ComponentNoiseRule rule);
/// "share" or "innovation". False if unknown.
bool ParseComponentNoiseRule(const std::string& text, ComponentNoiseRule* rule);

/// q and R of one filter.
struct FilterNoise {
  double q = -1.0;  ///< units of x^2; < 0: kalman::DefaultNoise from r (innovation matching)
  double r = 0.0;   ///< units of x^2
  /// share >= variance under kShareOfInnovation: the component is judged pure white noise; its
  /// filter gets q = 0 and starts from P(0|0) = 0, so it outputs the component's mean.
  bool pure_noise = false;
};

/// The rule applied to one component: its white share (ShareWhiteNoise), its variance and its AR
/// innovation variance sigma_e^2, all in units of x^2.
FilterNoise ComponentFilterNoise(ComponentNoiseRule rule, double white_share, double variance,
                                 double innovation_variance);

/// Variance of every IMF, then of the residue, units of x^2 (about each component's mean).
std::vector<double> ComponentVariances(const emd::EmdResult& decomposition);

/// sigma_w^2 of step 1, units of x^2. 0 for fewer than 3 samples. When more than half of the
/// differences are equal (coarse quantization: MAD 0), var(diff x) / 2 instead.
double WhiteNoiseVariance(const Eigen::VectorXd& x);

/// Step 2: R_k for each IMF from sigma_w^2, the IMFs' mean periods (samples) and the IMFs'
/// variances (units of x^2). Non-positive or non-finite periods get no share.
std::vector<double> ShareWhiteNoise(double white_noise_variance,
                                    const std::vector<double>& mean_period_samples,
                                    const std::vector<double>& imf_variance);

/// Mean period of every IMF, then of the residue, samples. The residue counts as one cycle over
/// the record (period num_samples), so it gets a tiny share and its filter follows it.
std::vector<double> ComponentPeriods(const emd::EmdResult& decomposition, Eigen::Index num_samples);

/// Steps 1-2 applied to a decomposition of a signal of `num_samples` samples: R_k for every IMF,
/// then the residue last (ComponentPeriods, ComponentVariances).
std::vector<double> ShareWhiteNoise(double white_noise_variance,
                                    const emd::EmdResult& decomposition, Eigen::Index num_samples);

}  // namespace fogpipe::method
