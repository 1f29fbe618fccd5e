// Is the rate the output of an angle counter, and is its quantization coarse? (`fogpipe compare`,
// a diagnostic of the recording beside the views.)
//
// Why. Many gyros (FOG and RLG electronics, encoders) output an angle counter: the angle is
// theta_k = q round(x_k / q) + const, x the true integrated angle, and the rate is
// (theta_k - theta_{k-1}) / dt. Every angle increment a_k = rate_k dt is then c + q n_k, n_k an
// integer (c an offset, e.g. a constant removed after counting). The quantization error
// e_k = theta_k - x_k enters the rate as (e_k - e_{k-1}) / dt. When the angle noise per sample is
// well above q, or a dither of about a step is added before the counter, e_k is white (uniform,
// variance q^2 / 12 without dither; Widrow & Kollar 2008, ch. 4-5) and is the IEEE Std 952 angle
// quantization Q (Annex C: Q = q / sqrt(12)), which the model already holds. When the angle noise
// per sample is below about q and no dither is added, e_k is a deterministic function of the
// slowly moving phase x_k / q mod 1: a sawtooth driven by the bias and the slow drift, whose
// differences are a comb of idle tones (Gray 1990) that no catalog term describes.
//
// The lattice. The increments of a strided subsample (at most `max_sorted_samples`) are sorted
// and grouped into distinct levels (values within 1e-6 of the largest |a_k| apart are one level:
// float32 storage keeps about 7 digits). Continuous data have nearly as many levels as samples
// and are rejected there. Otherwise the step is the median gap between neighbouring levels,
// refined with the offset by least squares of the levels on their integer indices (weighted by
// the levels' counts); then every increment of the record is tested: the fraction within
// `level_tolerance` q of the lattice c + q Z must be at least `min_fraction`, and the levels the
// record spans, (max a - min a) / q, at most `max_levels` (floating-point rounding is a lattice
// too, with millions of levels). On continuous data the fraction is about 2 level_tolerance, so
// the false-alarm rate is nil for any record of more than a few samples.
//
// Coarse. Under a white error the increments are white noise plus the MA(1) of e_k - e_{k-1}:
// their autocorrelations vanish at lags >= 2 (the angle random walk's increments are white; bias
// instability and rate random walk add a negligible correlation per sample). Ljung & Box's (1978)
// portmanteau over lags 2..L, with Bartlett's (1946) variance of r_h for an MA(1),
// (1 + 2 r_1^2) / n, is then chi-square(L - 1):
//   Q = n sum_{h=2..L} r_h^2 / (1 + 2 r_1^2).
// The idle tones of a coarse error correlate the increments at every lag up to the sawtooth's
// period. The error is called coarse when Q exceeds the chi-square(L - 1) quantile at
// 1 - `coarse_level` and the increments' sample standard deviation is at most
// `max_spread_steps` q (the angle moves by less than about a step from one sample to the next;
// a rate quantizer much finer than the noise, such as a MEMS ADC whose record has a vibration
// line, correlates the increments too, but spreads them over many steps).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>

namespace fogpipe::model {

struct AngleLatticeOptions {
  int max_sorted_samples = 100000;  ///< the strided subsample whose levels are sorted
  double level_tolerance = 1e-3;    ///< |a - lattice| <= this * q is on the lattice
  double min_fraction = 0.999;      ///< on-lattice fraction of the record's increments
  double max_levels = 65536;        ///< (max a - min a) / q above this: not a counter
  int whiteness_lags = 20;          ///< L, the portmanteau's last lag (lags 2..L are tested)
  double coarse_level = 1e-6;       ///< false-alarm rate of the coarse test under a white error
  double max_spread_steps = 1.0;    ///< sd of the increments, in steps, for a coarse error
  bool IsValid(std::string* error) const;
};

/// What DetectAngleLattice found (SI; the step also in arcsec for reports).
struct AngleLattice {
  bool evaluated = false;   ///< false: too few finite samples or invalid options
  bool on_lattice = false;  ///< every increment (up to min_fraction) is c + q n
  double step_rad = std::numeric_limits<double>::quiet_NaN();     ///< q, angle per count
  double step_se_rad = std::numeric_limits<double>::quiet_NaN();  ///< its SE (>= 2^-24 q)
  double offset_rad = std::numeric_limits<double>::quiet_NaN();   ///< c, per sample
  double on_lattice_fraction = 0;  ///< fraction of the record's increments on the lattice
  int levels = 0;                  ///< distinct levels in the sorted subsample
  double spread_steps = std::numeric_limits<double>::quiet_NaN();         ///< sd(a) / q
  double lag1_correlation = std::numeric_limits<double>::quiet_NaN();     ///< r_1 of the increments
  double whiteness_statistic = std::numeric_limits<double>::quiet_NaN();  ///< Q above
  double whiteness_critical = std::numeric_limits<double>::quiet_NaN();   ///< its critical value
  int whiteness_dof = 0;                                                  ///< L - 1
  bool coarse = false;  ///< on the lattice, error not white, spread below max_spread_steps
  std::string message;  ///< one line, e.g. "angle counter, step 6.93 arcsec, coarse (...)"
};

/// Tests the rate for an angle-counter lattice and its error for whiteness (see the header
/// comment). Non-finite samples are skipped.
AngleLattice DetectAngleLattice(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                                const AngleLatticeOptions& options = AngleLatticeOptions());

}  // namespace fogpipe::model
