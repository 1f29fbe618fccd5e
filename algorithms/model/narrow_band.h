// The `narrow_band` term of the gyro model: a vibration or structural band, i.e. a lightly damped
// second-order resonance driven by white noise (x'' + 2 zeta w0 x' + w0^2 x = white), added to the
// rate. Parameters: centre frequency f0 = w0 / (2 pi) (Hz), damping ratio zeta (half-power
// bandwidth 2 zeta f0) and rms sigma (rad/s; the process variance is sigma^2). One-sided PSD
//
//   S(f) = 8 zeta w0^3 sigma^2 / ((w0^2 - w^2)^2 + (2 zeta w0 w)^2),   w = 2 pi f,
//
// whose integral over f in [0, inf) is sigma^2 and whose peak is sigma^2 / (pi zeta f0).
//
// Allan variance, exact for the continuous process: with X(t) the integral of the rate and
// D(t) = E[(X(s + t) - X(s))^2] = 2 int_0^t (t - u) R(u) du its structure function,
// sigma^2(tau) = (4 D(tau) - D(2 tau)) / (2 tau^2) (the Allan variance is half the mean square of
// the second difference of X over tau). The autocovariance of the resonance (zeta < 1) is
// R(u) = Re[C exp(lambda u)] with lambda = -zeta w0 + i w_d, w_d = w0 sqrt(1 - zeta^2) and
// C = sigma^2 (1 - i zeta w0 / w_d), so D(t) = 2 Re[C (exp(lambda t) - 1 - lambda t) / lambda^2]
// in closed form. It equals the PSD transfer function of IEEE Std 952-1997 / NIST SP 1065,
// sigma^2(tau) = 2 int_0^inf S(f) sin^4(pi f tau) / (pi f tau)^2 df (narrow_band_test checks it).
//
// Estimation (`FitNarrowBand`): it is a spectral feature, so it is fitted on the Welch PSD of the
// residual, not on the Allan curve (whose octave taus cannot resolve f0 or zeta): Whittle's (1953)
// likelihood of the Welch bins, each psd_k ~ S_k chi2(nu)/nu, over a window around the failing
// band of the frequency view, with S_k = a * background_k + band_k and a free local level a of the
// background (the rest of the model), maximised by Nelder-Mead in (ln a, ln f0, ln zeta, ln
// sigma^2) from the band's centre, extent and excess power. Standard errors from the inverse
// Hessian of -ln L, inflated for the correlation of adjacent Hann bins (see narrow_band.cpp).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/model/spectrum.h"

namespace fogpipe::model {

struct NarrowBand {
  double f0_hz = 0, f0_se_hz = 0;
  double zeta = 0, zeta_se = 0;                ///< damping ratio (half-power bandwidth 2 zeta f0)
  double sigma_rad_s = 0, sigma_se_rad_s = 0;  ///< rms of the band (sqrt of its power)
  /// Standard error of the half-power bandwidth 2 zeta f0, Hz, from the joint covariance of f0
  /// and zeta (their estimates are correlated: both shape the same peak).
  double bandwidth_se_hz = 0;
  /// Drop of -2 ln L (Whittle, bin-correlation corrected) against the background alone over the
  /// window, and the number of effectively independent bins of the tested spectrum (for BIC).
  double minus_two_log_likelihood_drop = 0;
  double effective_bins = 0;
};

/// The half-power (-3 dB) bandwidth of the band, 2 zeta f0, Hz.
inline double HalfPowerBandwidthHz(const NarrowBand& band) { return 2 * band.zeta * band.f0_hz; }

/// One-sided PSD of the band at f, (rad/s)^2/Hz.
double NarrowBandOneSidedPsd(const NarrowBand& band, double frequency_hz);

/// Allan variance of the band at tau, (rad/s)^2 (closed form above).
double NarrowBandAllanVariance(const NarrowBand& band, double tau_s);

/// n samples at sample_rate_hz of the band's process, rad/s: the resonance's state (x, x') sampled
/// exactly (its transition exp(A / fs) and the stationary covariance diag(sigma^2, w0^2 sigma^2)
/// give the step's noise covariance), started from the stationary law, so that the samples have
/// the autocovariance R(u) above at every lag. With block > 1, n means of `block` consecutive
/// such samples (what a residual averaged in blocks holds). zeta in (0, 1); `seed` drives its
/// own stream (simulation::RandomSource).
Eigen::VectorXd SimulateNarrowBand(const NarrowBand& band, long n, double sample_rate_hz,
                                   std::uint64_t seed, long block = 1);

/// Where to look: the failing band of the frequency view (views.h Failure) that starts the fit.
struct NarrowBandStart {
  double from_hz = 0, to_hz = 0, center_hz = 0;
  double excess_power = 0;  ///< (rad/s)^2
};

struct NarrowBandFitResult {
  bool ok = false;
  NarrowBand band;
  std::string message;
};

/// Fits one band to the Welch PSD `welch` (one-sided) with `background` the model PSD of the
/// other terms at welch.frequency_hz (its local level is free) and `fixed` that of the bands
/// already in the model (as it is; empty: none); bins below first_bin are not used (Hann
/// leakage).
NarrowBandFitResult FitNarrowBand(const Spectrum& welch, const std::vector<double>& background,
                                  const std::vector<double>& fixed, int first_bin,
                                  const NarrowBandStart& start);

}  // namespace fogpipe::model
