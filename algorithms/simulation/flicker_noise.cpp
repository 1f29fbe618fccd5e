#include "algorithms/simulation/flicker_noise.h"

#include <complex>
#include <unsupported/Eigen/FFT>
#include <vector>

namespace fogpipe::simulation {

Eigen::VectorXd KasdinCoefficients(Eigen::Index n, double alpha) {
  Eigen::VectorXd h(n);
  if (n == 0) return h;
  h[0] = 1.0;
  for (Eigen::Index k = 1; k < n; ++k) {
    h[k] = h[k - 1] * (static_cast<double>(k) - 1.0 + 0.5 * alpha) / static_cast<double>(k);
  }
  return h;
}

Eigen::Index FastFftSize(Eigen::Index n) {
  for (Eigen::Index m = std::max<Eigen::Index>(n, 4);; ++m) {
    if (m % 4 != 0) continue;
    Eigen::Index r = m;
    for (Eigen::Index p : {2, 3, 5}) {
      while (r % p == 0) r /= p;
    }
    if (r == 1) return m;
  }
}

Eigen::VectorXd FlickerRateNoise(Eigen::Index n, double sample_rate_hz, double b_rad_s,
                                 RandomSource* rng) {
  Eigen::VectorXd out(n);
  if (n == 0) return out;
  const Eigen::Index size = FastFftSize(2 * n - 1);
  const size_t half = static_cast<size_t>(size / 2 + 1);
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);

  // The filter, zero-padded, straight into the transform buffer (same recursion as
  // KasdinCoefficients, without a second copy of n values).
  std::vector<double> buffer(static_cast<size_t>(size), 0.0);
  buffer[0] = 1.0;
  for (Eigen::Index k = 1; k < n; ++k) {
    buffer[k] = buffer[k - 1] * (static_cast<double>(k) - 0.5) / static_cast<double>(k);
  }
  std::vector<std::complex<double>> filter_spectrum(half);
  fft.fwd(filter_spectrum.data(), buffer.data(), size);

  // sigma_w = B: see the header. The white noise is drawn after the filter so that the draw order
  // (and hence the realisation for a seed) does not depend on the FFT size.
  for (Eigen::Index k = 0; k < n; ++k) buffer[k] = b_rad_s * rng->Normal();
  std::fill(buffer.begin() + n, buffer.end(), 0.0);
  std::vector<std::complex<double>> spectrum(half);
  fft.fwd(spectrum.data(), buffer.data(), size);
  for (size_t i = 0; i < half; ++i) spectrum[i] *= filter_spectrum[i];
  std::vector<std::complex<double>>().swap(filter_spectrum);  // release before the inverse

  fft.inv(buffer.data(), spectrum.data(), size);  // Eigen's inverse divides by size
  std::copy(buffer.begin(), buffer.begin() + n, out.data());
  return out;
}

}  // namespace fogpipe::simulation
