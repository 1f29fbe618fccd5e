// Bias instability as flicker (1/f) rate noise, by Kasdin's fractional-integration filter.
//
// Kasdin N. J., "Discrete simulation of colored noise and stochastic processes and 1/f^alpha power
// law noise generation", Proc. IEEE 83(5), 1995 (first in Kasdin & Walter, IEEE FCS 1992): white
// noise w_k of variance sigma_w^2 filtered by H(z) = (1 - z^-1)^(-alpha/2), whose impulse response
// is
//   h_0 = 1,  h_k = h_{k-1} (k - 1 + alpha/2) / k,
// has the two-sided PSD  S(f) = sigma_w^2 dt / |2 sin(pi f dt)|^alpha  for |f| < fs/2.
// With alpha = 1 and sigma_w = B this is B^2 / (2 pi f) at f << fs, the IEEE Std 952-1997 C.3
// bias-instability PSD, whose Allan floor is sqrt(2 ln 2 / pi) B = 0.664 B.
//
// The filter is applied over the whole record (h truncated at the record length, which is exact
// for the first n outputs) as one linear convolution by real FFT, zero-padded to a size >= 2n - 1
// whose only prime factors are 2, 3 and 5. The process starts at rest at t = 0 (like a random walk
// started at 0), as in Kasdin's construction. Memory: the padded buffer, two half spectra and
// kissfft's scratch and twiddle tables, about 10 doubles per padded sample at the peak
// (measured peak RSS of `fogpipe simulate` for 24 h at 100 Hz: see the report).
#pragma once

#include <Eigen/Core>

#include "algorithms/simulation/random.h"

namespace fogpipe::simulation {

/// The first n coefficients of Kasdin's filter (1 - z^-1)^(-alpha/2).
Eigen::VectorXd KasdinCoefficients(Eigen::Index n, double alpha);

/// Flicker rate noise with two-sided PSD B^2 / |2 sin(pi f dt)| dt ~ B^2 / (2 pi f): the IEEE
/// bias-instability term for B in rad/s. The white-noise level sigma_w = B does not depend on
/// sample_rate_hz (the dt in S(f) cancels at low frequency); it is taken for a uniform signature.
Eigen::VectorXd FlickerRateNoise(Eigen::Index n, double sample_rate_hz, double b_rad_s,
                                 RandomSource* rng);

/// The smallest integer >= n whose prime factors are only 2, 3 and 5 and that is a multiple of 4
/// (the sizes for which Eigen's kissfft runs its fast real-input path).
Eigen::Index FastFftSize(Eigen::Index n);

}  // namespace fogpipe::simulation
