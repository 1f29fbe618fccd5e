// The white measurement-noise variance R given to each component's Kalman filter.
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
// Why not R = the AR innovation variance or Q = innovation variance and R = sigma_w^2 for the
// whole signal: the AR innovation variance of a noisy component already contains its share of the
// measurement noise (method.md, "What to keep in mind"). Giving the filter the full sigma_w^2 as R
// on every IMF would count the white noise once per IMF; giving R = sigma_w^2 and
// Q = innovation variance would count it twice. Here each IMF's R is its own share, and the Kalman
// engine's default q rule (kalman/noise_defaults.h) removes that share from the innovation
// variance.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "algorithms/emd/emd.h"

namespace fogpipe::method {

/// sigma_w^2 of step 1, units of x^2. 0 for fewer than 3 samples. When more than half of the
/// differences are equal (coarse quantization: MAD 0), var(diff x) / 2 instead.
double WhiteNoiseVariance(const Eigen::VectorXd& x);

/// Step 2: R_k for each IMF from sigma_w^2, the IMFs' mean periods (samples) and the IMFs'
/// variances (units of x^2). Non-positive or non-finite periods get no share.
std::vector<double> ShareWhiteNoise(double white_noise_variance,
                                    const std::vector<double>& mean_period_samples,
                                    const std::vector<double>& imf_variance);

/// Steps 1-2 applied to a decomposition of a signal of `num_samples` samples: R_k for every IMF,
/// then the residue last. The residue counts as one cycle over the record (period num_samples),
/// so it gets a tiny share and its filter follows it.
std::vector<double> ShareWhiteNoise(double white_noise_variance,
                                    const emd::EmdResult& decomposition, Eigen::Index num_samples);

}  // namespace fogpipe::method
