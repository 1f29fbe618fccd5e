// Closed-form Allan variances of the gyro noise terms (IEEE Std 952-1997 Annex C; NIST SP 1065),
// so that a model-fitting step can combine them: sigma^2(tau) = sum of TermAllanVariance(...).
// Units are SI: rate in rad/s, so every variance is in (rad/s)^2.
#pragma once

namespace fogpipe::allan {

enum class Term {
  kQuantization,     ///< Q [rad]:                 3 Q^2 / tau^2
  kAngleRandomWalk,  ///< N [rad/sqrt(s)]:         N^2 / tau
  kBiasInstability,  ///< B [rad/s]:               (2 ln2 / pi) B^2  (flat floor of flicker)
  kRateRandomWalk,   ///< K [rad/s/sqrt(s)]:       K^2 tau / 3
  kRateRamp,         ///< R [rad/s^2]:             R^2 tau^2 / 2
  kSinusoid,         ///< W [rad/s] at f0 [Hz]:    W^2 (sin^2(pi f0 tau) / (pi f0 tau))^2
  kGaussMarkov,      ///< sigma [rad/s], Tc [s]:   first-order Gauss-Markov, see below
};

struct TermParams {
  /// Q, N, B, K, R, W or sigma, in the SI unit given for the term.
  double amplitude = 0.0;
  /// Sinusoid frequency f0 [Hz] (kSinusoid only).
  double frequency_hz = 0.0;
  /// Correlation time Tc [s] (kGaussMarkov only).
  double correlation_time_s = 0.0;
};

/// Allan variance [(rad/s)^2] of one term at averaging time tau_s > 0.
///
/// Bias instability: the exact Allan variance of 1/f rate noise S(f) = B^2 / (2 pi f) (two-sided,
/// IEEE 952 convention) is (2 ln 2 / pi) B^2 at every tau; a real gyro's flicker region is bounded
/// by a cut-off f0, which only bends the curve outside the flat floor. Fitting it as a constant is
/// the standard practice (IEEE 952 C.3) and is what is modelled here.
///
/// Gauss-Markov x' = -x / Tc + w with stationary variance sigma^2: with q = 2 sigma^2 / Tc the
/// white-noise intensity and u = tau / Tc,
///   sigma_A^2(tau) = (q Tc^2 / tau) [1 - (3 - 4 e^{-u} + e^{-2u}) / (2u)]
/// (IEEE 952 Annex C, exponentially correlated noise); it rises as q tau / 3 (a rate random walk
/// with K^2 = q) for tau << Tc, falls as q Tc^2 / tau (an ARW with N^2 = q Tc^2) for tau >> Tc, and
/// peaks at ~0.62 sigma near tau = 1.89 Tc.
///
/// Sinusoid W sin(2 pi f0 t): peak ~0.725 W at tau ~0.371 / f0, zero at tau = k / f0.
double TermAllanVariance(Term term, const TermParams& params, double tau_s);

/// Local log-log slope d ln sigma / d ln tau of the five IEEE terms: -1, -1/2, 0, +1/2, +1.
double TermSlope(Term term);

}  // namespace fogpipe::allan
