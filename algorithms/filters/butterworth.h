// Zero-phase Butterworth low-pass (forward-backward, as MATLAB/scipy filtfilt) with its cutoff
// chosen by generalised cross-validation (Craven & Wahba 1979), without the truth.
//
// Design: the analog Butterworth prototype of even order n mapped by the bilinear transform with
// the cutoff prewarped (Oppenheim & Schafer, ch. 7), run as n/2 biquad sections (transposed direct
// form II). The forward-backward cascade has the real, non-negative response
//   |H(f)|^2 = 1 / (1 + (tan(pi f / fs) / tan(pi fc / fs))^(2n)),
// which tends to the analog 1 / (1 + (f / fc)^(2n)) for f << fs.
// Edges: the ends are extended by odd reflection (2 x_0 - x_k, as filtfilt does) over eight cutoff
// periods, and each pass starts every section in the steady state of its first input (as
// lfilter_zi), so a line passes through both ends without a transient.
//
// GCV (Craven & Wahba 1979): the filter is a linear smoother yhat = S y, and
//   GCV(fc) = N ||y - yhat||^2 / (N - tr S)^2.
// Both terms come from one FFT. The line through the two end samples is removed (the zero-phase
// filter passes lines exactly) and the rest extended antisymmetrically about its zero ends into a
// continuous periodic sequence of length L = 2M - 2 (M <= N, L a fast FFT size): on it the
// forward-backward filter with odd-reflection ends is the circulant with eigenvalues
// |H(k fs / L)|^2, so ||y - yhat||^2 = (1 / 2L) sum_k (1 - |H_k|^2)^2 |Y_k|^2 (half of the
// extension's residual) and tr S = (M / L) sum_k |H_k|^2. (A plain DFT of y instead adds the jump
// of its periodic extension and misjudges records whose truth ends at a new level.) Each cutoff
// then costs one pass over the L/2 bins. Search: a log grid of cutoffs, then golden-section
// refinement of log fc around the best grid point.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/common/status.h"

namespace fogpipe::filters {

/// One biquad section: y = b0 x + b1 x[-1] + b2 x[-2] - a1 y[-1] - a2 y[-2].
struct Biquad {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
};

/// Sections of a digital Butterworth low-pass of even `order` (2 or 4), cutoff_hz < fs / 2.
std::vector<Biquad> ButterworthSections(int order, double cutoff_hz, double sample_rate_hz);

/// The zero-phase (forward-backward) power response at f_hz: the closed form in the header.
double ZeroPhaseButterworthResponse(int order, double cutoff_hz, double sample_rate_hz,
                                    double f_hz);

/// Forward-backward filtering of x with the sections (odd-reflection ends, steady-state starts).
/// Same length as x; x shorter than 2 samples is returned unchanged. At most two sections (the
/// cascades of ButterworthSections); more throw std::invalid_argument.
Eigen::VectorXd FilterForwardBackward(const std::vector<Biquad>& sections, const Eigen::VectorXd& x,
                                      Eigen::Index pad_samples);
/// The same into *out, with *work holding the right end's extension (pad samples): both are reused
/// across calls and grow only when they must (fresh pages cost more than the filtering on long
/// records). Equal to the allocating form to the last bit. *out must not be x.
void FilterForwardBackward(const std::vector<Biquad>& sections, const Eigen::VectorXd& x,
                           Eigen::Index pad_samples, std::vector<double>* work,
                           Eigen::VectorXd* out);

struct ButterworthOptions {
  /// Filter order (of each pass): 2 or 4. Default 4.
  int order = 4;
  /// Cutoff, Hz; 0 (default) = by GCV.
  double cutoff_hz = 0.0;
  /// GCV search: log grid from min_cycles cycles per record up to max_fraction_of_nyquist x fs/2,
  /// grid_points points, then golden-section refinement to relative_tolerance in fc.
  double min_cycles = 2.0;
  double max_fraction_of_nyquist = 0.9;
  int grid_points = 16;
  double relative_tolerance = 1e-2;

  bool IsValid(std::string* error) const;
};

struct ButterworthResult {
  Eigen::VectorXd output;       ///< filtered x, units of x
  double cutoff_hz = 0.0;       ///< the cutoff used
  double gcv = 0.0;             ///< GCV score at the cutoff, (units of x)^2 (NaN when given)
  double trace = 0.0;           ///< tr S at the cutoff (effective parameters), per N samples
  bool at_lower_bound = false;  ///< GCV chose the lowest cutoff of its grid
  Termination termination = Termination::kInvalidOptions;
  std::string message;
};

/// The odd-reflection pad used for a cutoff: eight cutoff periods (the start transient of a
/// ramp decays as exp(-2 pi sin(pi / 8) fc t) for order 4, to 4e-9 after eight periods).
Eigen::Index ButterworthPad(double cutoff_hz, double sample_rate_hz);

/// GCV score of the zero-phase Butterworth (see above) of the first M samples of x. Exposed for
/// tests; `x` must have >= 8 samples.
class ButterworthGcv {
 public:
  ButterworthGcv(const Eigen::VectorXd& x, double sample_rate_hz, int order);
  /// GCV(fc), (units of x)^2; *trace (optional): tr S for the M samples; *rss (optional):
  /// ||y - yhat||^2 over them.
  double Score(double cutoff_hz, double* trace = nullptr, double* rss = nullptr) const;
  /// M: the samples the score uses.
  Eigen::Index samples() const { return samples_; }

 private:
  int order_;
  double sample_rate_hz_;
  Eigen::Index samples_ = 0;        // M
  double length_ = 0.0;             // L = 2M - 2
  std::vector<double> tan2_;        // tan^2(pi k / L), k = 0 .. L/2
  std::vector<double> power_;       // weight_k |Y_k|^2 / (2 L)
  std::vector<double> tail_power_;  // sum of power_ from k on
  // The weight of bin k of a half spectrum with bins 0..half: 1 at DC and Nyquist, else 2.
  static double Weight(long k, long half) { return (k == 0 || k == half) ? 1.0 : 2.0; }
};

ButterworthResult ZeroPhaseButterworth(const Eigen::VectorXd& x, double sample_rate_hz,
                                       const ButterworthOptions& options);

}  // namespace fogpipe::filters
