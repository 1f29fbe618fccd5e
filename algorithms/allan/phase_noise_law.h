// The law of an overlapping Allan (or Hadamard) variance estimate of phase noise with few
// averages: white PM (alpha = 2) and flicker PM (alpha = 1).
//
// s2 / E[s2] = sum_j mu_j chi2_1 with mu the eigenvalues of the covariance C of the M phase
// differences D_i (estimate_law.h). For frequency noise D_i is continuous in its start i and a
// coarse sample of C gives its eigenvalues; for phase noise it is not: C(i, j) = c(j - i) has
// spikes at the lags 0, +-m, .., +-d m (white PM is nothing else; flicker PM adds logarithmic
// cusps there to a smooth background), which point samples miss or overweight. Flicker PM's
// fluctuation is carried by a few large eigenvalues (the lowest lobe of sin^4(pi f m) / f, one
// per average) on top of a near-constant sum of many small ones, so chi-square with the same
// EDF gives too wide 68.3 % intervals at 4-8 averages.
//
// The large eigenvalues are the Rayleigh-Ritz values of C compressed onto K = 128 vectors constant
// on blocks of consecutive starts (they interlace below C's own: Courant-Fischer); block sums of c
// are exact sums near the spikes and Gauss-Legendre integrals between them. What the compression
// leaves, tr C - sum r and tr C^2 - sum r^2 (both exact), is a moment-matched scaled chi-square
// (Satterthwaite 1946): a sum of many small weights. Against the eigenvalues of the full M x M
// covariance the quantiles agree to 1e-3 (phase_noise_law_test).
//
// The phase's generalised autocovariance per unit level, in sample lags u, with the rate's
// two-sided spectrum S_y(f) = h (2 sin pi f)^alpha (Kasdin & Walter 1992's discrete power laws):
//   white PM:   delta(u)
//   flicker PM: -V(u) / 2,  V(u) = E (x_u - x_0)^2 = (2 / pi) (psi(|u| + 1/2) - psi(1/2)),
// from the rate's autocovariance -1 / (pi (k^2 - 1/4)) ((1 - B)^(1/2) applied to white noise),
// whose partial sums telescope: V(u) - V(u - 1) = (2 / pi) / (u - 1/2).
#pragma once

#include "algorithms/allan/estimate_law.h"

namespace fogpipe::allan {

/// The law of s2 / E[s2] for the overlapping d-th difference variance (d = 2 OADEV, 3 OHDEV) at
/// averaging factor m with `count` differences, for white PM (alpha = 2) or flicker PM
/// (alpha = 1). Empty for any other alpha or d, or when the row does not have FewAverages.
WeightedChiSquareLaw PhaseNoiseLaw(int d, int alpha, long long m, long long count);

/// The EDF of the same estimate, tr(C)^2 / tr(C^2) (Greenhall & Riley's definition, 2 E[s2]^2 /
/// Var s2), at any number of averages; NaN for any other alpha or d. For white PM it is
/// Greenhall's; for flicker PM it is 11-16 % above his (his kernel is not the sampled
/// Kasdin-Walter process, and a flicker PM EDF depends on the high-frequency cutoff).
double PhaseNoiseEdf(int d, int alpha, long long m, long long count);

/// c(l) = Cov(D_i, D_{i+l}) per unit level for the same noises at an integer lag (for tests).
double PhaseNoiseDifferenceCovariance(int d, int alpha, long long m, long long lag);

}  // namespace fogpipe::allan
