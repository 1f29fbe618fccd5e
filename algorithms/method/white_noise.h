// The Kalman measurement-noise variance R (and the rule for q) of each component's filter.
//
// Rule (documented in schemas/results-v2.md as well):
//  1. The raw signal's white measurement noise has two parts, estimated jointly from its first
//     and second differences: white rate noise (angle random walk N) of variance u per sample,
//     and white angle noise (quantization Q), which enters the rate as e_t - e_{t-1} with
//     var(e_t) = v (rate units). With V_1 = var(x_t - x_{t-1}) = 2u + 6v and
//     V_2 = var(x_t - x_{t-2}) = 2u + 4v:  v = (V_1 - V_2) / 2,  u = (3 V_2 - 2 V_1) / 2, and the
//     per-sample variance of both, u + 2v, is V_2 / 2 (IEEE Std 952 annex C gives the two terms'
//     Allan variances; these are their per-sample forms). Each variance is a robust scale,
//     (1.4826 MAD)^2: slower terms (bias instability, rate random walk, ramps) barely change
//     differences over one or two samples, and the MAD ignores steps and gross errors. The MAD of
//     first differences alone, V_1 / 2 = u + 3v, counts the angle noise three times instead of
//     twice. (u = N^2 fs and v = Q^2 fs^2 for N in rad/sqrt(s), Q in rad, fs in Hz.)
//  2. Those variances are shared among the IMFs as EMD shares such noise: EMD acts on fractional
//     Gaussian noise as a dyadic filter bank whose IMF energies scale with the mean period T_k as
//     T_k^(2H - 2) (Flandrin, Rilling & Goncalves 2004, IEEE SPL 11:112; Wu & Huang 2004, Proc.
//     R. Soc. A 460:1597): T^-1 for white noise (H = 1/2), T^-3 for the f^2 rate spectrum of white
//     angle noise (a differenced white noise, H = -1/2). So IMF k receives
//     u (1/T_k) / sum_j (1/T_j) + 2v (1/T_k^3) / sum_j (1/T_j^3), capped at the IMF's own variance.
//     The residue (a trend) counts as one cycle over the record (T = N): a tiny share, so that
//     its filter follows it.
//
//  3. The share is band-passed noise, not white: EMD makes it predictable, so an IMF's AR
//     innovation variance sigma_e^2 is usually far below its share. Handing the share itself to
//     the filter as white R leaves no room for process noise: the moment match of
//     kalman/noise_defaults.h, H P H' + R = sigma_e^2, then clamps q to 0, the gain decays to zero
//     and the output is the AR model running free, which can raise the Allan deviation instead of
//     lowering it. So R is the white FRACTION of the component's one-step prediction error
//     instead:
//        R_k = (share_k / var_k) sigma_e,k^2,   q_k from H P H' + R_k = sigma_e,k^2
//        (noise_defaults.h)
//     A component that is mostly signal (share << variance) gets R << sigma_e^2 and is followed;
//     one that is mostly noise gets q -> 0 and is suppressed; q/R depends on the white fraction,
//     not on how smooth the IMF is, so slow IMFs whose sigma_e^2 is 1e-20 of their variance are
//     neither frozen nor left unfiltered. A component whose share reaches its variance (the cap of
//     step 2) is judged pure noise: q = 0 and P(0|0) = 0, so its filter outputs its mean instead
//     of extrapolating its AR model from a fitted initial state.
//     Measurements (a real record; sweeps on simulated moving-rate records): docs/filtering.md,
//     "Per-component Kalman filters". The stored fields: schemas/results-v2.md.
//
// Why not R = u + 2v (the whole white level) on every IMF or Q = innovation variance with R = u +
// 2v: the AR innovation variance of a noisy component already contains its share of the measurement
// noise (docs/method.md, "Cautions"); the whole level as R on every IMF would count the
// white noise once per IMF, and R = u + 2v with Q = innovation variance would count it twice.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/common/for_each.h"
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

/// Variance of one component about its mean, units of x^2 (0 when empty).
double ComponentVariance(const Eigen::VectorXd& component);

/// ComponentVariance of every IMF, then of the residue.
std::vector<double> ComponentVariances(const emd::EmdResult& decomposition);

/// The white measurement noise of step 1, per sample, units of x^2.
struct WhiteNoiseLevels {
  double rate_variance = 0.0;   ///< u: white rate noise (angle random walk), N^2 fs
  double angle_variance = 0.0;  ///< v: white angle noise (quantization) in rate units, Q^2 fs^2
  /// Per-sample variance of both in the rate, u + 2v.
  double Total() const { return rate_variance + 2.0 * angle_variance; }
};

/// Step 1. Zeros for fewer than 4 samples. When more than half of some differences are equal
/// (coarse quantization: MAD 0), their plain mean square replaces the robust scale. The two
/// differences' scales are found through for_each (one after the other when it is empty).
WhiteNoiseLevels EstimateWhiteNoiseLevels(const Eigen::VectorXd& x, const ForEach& for_each = {});

/// Step 2: R_k for each IMF from the levels, the IMFs' mean periods (samples) and the IMFs'
/// variances (units of x^2). Non-positive or non-finite periods get no share.
std::vector<double> ShareWhiteNoise(const WhiteNoiseLevels& levels,
                                    const std::vector<double>& mean_period_samples,
                                    const std::vector<double>& imf_variance);

/// Mean period of every IMF (from decomposition.imf_info, so also when the IMFs were streamed
/// and not kept), then of the residue, samples. The residue counts as one cycle over the record
/// (period num_samples), so it gets a tiny share and its filter follows it.
std::vector<double> ComponentPeriods(const emd::EmdResult& decomposition, Eigen::Index num_samples);

/// Steps 1-2 applied to a decomposition of a signal of `num_samples` samples: R_k for every IMF,
/// then the residue last (ComponentPeriods, ComponentVariances).
std::vector<double> ShareWhiteNoise(const WhiteNoiseLevels& levels,
                                    const emd::EmdResult& decomposition, Eigen::Index num_samples);

}  // namespace fogpipe::method
