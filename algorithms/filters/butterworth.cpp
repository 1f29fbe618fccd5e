#include "algorithms/filters/butterworth.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <unsupported/Eigen/FFT>

#include "algorithms/filters/search.h"
#include "algorithms/model/spectrum.h"

namespace fogpipe::filters {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Starts section s in the steady state of its first input u (unity DC gain: output = input = u,
/// so z2 = (b2 - a2) u, z1 = (1 - b0) u) and runs it on that input: returns its first output.
double StartSection(const Biquad& s, double u, double* z1, double* z2) {
  *z1 = (1.0 - s.b0) * u;
  *z2 = (s.b2 - s.a2) * u;
  const double y = s.b0 * u + *z1;
  *z1 = s.b1 * u - s.a1 * y + *z2;
  *z2 = s.b2 * u - s.a2 * y;
  return y;
}

/// The recursion state of one pass of one or two sections: a pass may run over several segments
/// (RunPassSegment), each continuing where the one before stopped, with the arithmetic of a single
/// run over their concatenation.
struct PassState {
  double az1 = 0, az2 = 0, bz1 = 0, bz2 = 0;
  bool started = false;
};

/// Runs one section over the segment d in place, forward or backward; the pass starts in the
/// steady state of its first input.
/// (Sections are taken by value: the coefficients then stay in registers, as the stores into d
/// cannot alias them.)
template <bool kForward>
void RunSection(const Biquad s, PassState* state, double* d, Eigen::Index n) {
  double z1 = state->az1, z2 = state->az2;
  Eigen::Index i = 0;
  if (!state->started && n > 0) {
    double& first = d[kForward ? 0 : n - 1];
    first = StartSection(s, first, &z1, &z2);
    state->started = true;
    i = 1;
  }
  for (; i < n; ++i) {
    double& x = d[kForward ? i : n - 1 - i];
    const double y = s.b0 * x + z1;
    z1 = s.b1 * x - s.a1 * y + z2;
    z2 = s.b2 * x - s.a2 * y;
    x = y;
  }
  state->az1 = z1;
  state->az2 = z2;
}

/// Two sections in one pass, sample by sample: each does the arithmetic of a pass of its own over
/// the output of the one before (the same numbers, section b started in the steady state of a's
/// first output), but the two recurrences, each bound by the latency of its multiplies and adds,
/// overlap. Half the time of two passes.
template <bool kForward>
void RunSectionPair(const Biquad a, const Biquad b, PassState* state, double* d, Eigen::Index n) {
  double az1 = state->az1, az2 = state->az2, bz1 = state->bz1, bz2 = state->bz2;
  Eigen::Index i = 0;
  if (!state->started && n > 0) {
    double& first = d[kForward ? 0 : n - 1];
    first = StartSection(b, StartSection(a, first, &az1, &az2), &bz1, &bz2);
    state->started = true;
    i = 1;
  }
  for (; i < n; ++i) {
    double& x = d[kForward ? i : n - 1 - i];
    const double w = x;
    const double ya = a.b0 * w + az1;
    az1 = a.b1 * w - a.a1 * ya + az2;
    az2 = a.b2 * w - a.a2 * ya;
    const double yb = b.b0 * ya + bz1;
    bz1 = b.b1 * ya - b.a1 * yb + bz2;
    bz2 = b.b2 * ya - b.a2 * yb;
    x = yb;
  }
  *state = {az1, az2, bz1, bz2, state->started};
}

/// One segment of a pass of at most two sections (the cascades of ButterworthSections, order 2 or
/// 4), in place: forward, the segments in order; backward, the later segment first.
template <bool kForward>
void RunPassSegment(const std::vector<Biquad>& sections, PassState* state, double* d,
                    Eigen::Index n) {
  if (sections.size() == 2) {
    RunSectionPair<kForward>(sections[0], sections[1], state, d, n);
  } else if (sections.size() == 1) {
    RunSection<kForward>(sections[0], state, d, n);
  }
}

/// |H|^2 of the zero-phase cascade from u = (tan(pi f / fs) / tan(pi fc / fs))^2.
double PowerResponse(int order, double u) {
  const double u2 = u * u;
  return 1.0 / (1.0 + (order == 2 ? u2 : u2 * u2));
}

}  // namespace

std::vector<Biquad> ButterworthSections(int order, double cutoff_hz, double sample_rate_hz) {
  // Analog prototype pole pairs s^2 + 2 zeta s + 1, zeta_k = sin(pi (2k - 1) / (2n)); bilinear
  // transform s = (1 - z^-1) / (1 + z^-1) with the prewarped cutoff K = tan(pi fc / fs).
  const double k = std::tan(kPi * cutoff_hz / sample_rate_hz);
  const double k2 = k * k;
  std::vector<Biquad> sections;
  for (int i = 1; i <= order / 2; ++i) {
    const double zeta = std::sin(kPi * (2 * i - 1) / (2.0 * order));
    const double a0 = 1.0 + 2.0 * zeta * k + k2;
    Biquad s;
    s.b0 = k2 / a0;
    s.b1 = 2.0 * k2 / a0;
    s.b2 = k2 / a0;
    s.a1 = 2.0 * (k2 - 1.0) / a0;
    s.a2 = (1.0 - 2.0 * zeta * k + k2) / a0;
    sections.push_back(s);
  }
  return sections;
}

double ZeroPhaseButterworthResponse(int order, double cutoff_hz, double sample_rate_hz,
                                    double f_hz) {
  const double ratio =
      std::tan(kPi * f_hz / sample_rate_hz) / std::tan(kPi * cutoff_hz / sample_rate_hz);
  return PowerResponse(order, ratio * ratio);
}

Eigen::VectorXd FilterForwardBackward(const std::vector<Biquad>& sections, const Eigen::VectorXd& x,
                                      Eigen::Index pad_samples) {
  std::vector<double> work;
  Eigen::VectorXd out;
  FilterForwardBackward(sections, x, pad_samples, &work, &out);
  return out;
}

void FilterForwardBackward(const std::vector<Biquad>& sections, const Eigen::VectorXd& x,
                           Eigen::Index pad_samples, std::vector<double>* work,
                           Eigen::VectorXd* out) {
  if (sections.size() > 2) throw std::invalid_argument("FilterForwardBackward: at most 2 sections");
  if (out == &x) throw std::invalid_argument("FilterForwardBackward: out must not be x");
  const Eigen::Index n = x.size();
  if (n < 2) {
    *out = x;
    return;
  }
  // The series filtered is x extended by odd reflection about both end samples, pad samples each
  // side. It is never built: the forward pass runs over the left extension (generated a block at
  // a time; its outputs are not needed, as the backward pass ends at x[0]), then over x in *out,
  // then over the right extension in *work, whose forward outputs the backward pass starts from.
  // Memory: N + pad doubles instead of 2 (N + pad); the same arithmetic in the same order.
  const Eigen::Index pad = std::clamp<Eigen::Index>(pad_samples, 1, n - 1);
  PassState forward;
  constexpr Eigen::Index kBlock = 1024;
  double block[kBlock];
  for (Eigen::Index i0 = 0; i0 < pad; i0 += kBlock) {
    const Eigen::Index count = std::min(kBlock, pad - i0);
    for (Eigen::Index i = 0; i < count; ++i) block[i] = 2.0 * x[0] - x[pad - (i0 + i)];
    RunPassSegment<true>(sections, &forward, block, count);
  }
  *out = x;
  RunPassSegment<true>(sections, &forward, out->data(), n);
  if (static_cast<Eigen::Index>(work->size()) < pad) {
    // Exactly pad doubles: growing the vector would double its capacity (up to 2 N doubles).
    *work = std::vector<double>();
    work->resize(pad);
  }
  double* right = work->data();
  for (Eigen::Index i = 0; i < pad; ++i) right[i] = 2.0 * x[n - 1] - x[n - 2 - i];
  RunPassSegment<true>(sections, &forward, right, pad);
  PassState backward;
  RunPassSegment<false>(sections, &backward, right, pad);
  RunPassSegment<false>(sections, &backward, out->data(), n);
}

bool ButterworthOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* what) {
    if (error) *error = what;
    return false;
  };
  if (order != 2 && order != 4) return fail("butterworth order must be 2 or 4");
  if (!(cutoff_hz >= 0.0)) return fail("butterworth cutoff_hz must be >= 0 (0: by GCV)");
  if (!(min_cycles > 0.0)) return fail("butterworth min_cycles must be > 0");
  if (!(max_fraction_of_nyquist > 0.0 && max_fraction_of_nyquist < 1.0))
    return fail("butterworth max_fraction_of_nyquist must be in (0, 1)");
  if (grid_points < 3) return fail("butterworth grid_points must be >= 3");
  if (!(relative_tolerance > 0.0)) return fail("butterworth relative_tolerance must be > 0");
  return true;
}

Eigen::Index ButterworthPad(double cutoff_hz, double sample_rate_hz) {
  return static_cast<Eigen::Index>(std::ceil(8.0 * sample_rate_hz / cutoff_hz));
}

ButterworthGcv::ButterworthGcv(const Eigen::VectorXd& x, double sample_rate_hz, int order)
    : order_(order), sample_rate_hz_(sample_rate_hz) {
  // L = 2M - 2 a fast (even) FFT size with M <= N.
  long l = model::FastFftSizeAtMost(2 * static_cast<long>(x.size()) - 2);
  while (l % 2 != 0) l = model::FastFftSizeAtMost(l - 1);
  samples_ = l / 2 + 1;
  length_ = static_cast<double>(l);
  const Eigen::Index m = samples_;
  const long half = l / 2;
  // The DFT of the antisymmetric extension e (period L, e_0 = e_{M-1} = 0, e_{L-j} = -e_j) is
  // Y_k = -2i S_k with the sine transform S_k = sum_{j=1}^{M-2} d_j sin(pi j k / n), n = L / 2,
  // d the record less the line through its end samples. S comes from one real FFT of length n
  // (Numerical Recipes 12.3, sinft): y_j = sin(pi j / n) (d_j + d_{n-j}) + (d_j - d_{n-j}) / 2,
  // then S_{2k} = -Im Y'_k, S_1 = Re Y'_0 / 2, S_{2k+1} = S_{2k-1} + Re Y'_k (Y' = FFT(y), e^-i).
  // The extension itself is never built: about 3.5 M doubles in flight instead of 7 M.
  {
    const long n = half;
    const double x0 = x[0], slope = (x[m - 1] - x[0]) / static_cast<double>(m - 1);
    auto d = [&](long j) {
      return j <= 0 || j >= n ? 0.0 : x[j] - x0 - slope * static_cast<double>(j);
    };
    std::vector<double> y(n);
    y[0] = 0.0;
    for (long j = 1; j < n; ++j) {
      const double a = d(j), b = d(n - j);
      y[j] =
          std::sin(kPi * static_cast<double>(j) / static_cast<double>(n)) * (a + b) + 0.5 * (a - b);
    }
    std::vector<std::complex<double>> spectrum;
    {
      Eigen::FFT<double> fft;
      fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
      fft.fwd(spectrum, y);
    }
    y = std::vector<double>();
    // S_k into power_ (S_n = 0: sin(pi j) = 0), then |Y_k|^2 = 4 S_k^2 in place.
    std::vector<double>& sine = power_;
    sine.assign(half + 1, 0.0);
    const long bins = static_cast<long>(spectrum.size());  // n / 2 + 1
    for (long k = 0; k < bins && 2 * k < n; ++k) sine[2 * k] = -spectrum[k].imag();
    if (n > 1) sine[1] = 0.5 * spectrum[0].real();
    for (long k = 1; k < bins && 2 * k + 1 < n; ++k) {
      sine[2 * k + 1] = sine[2 * k - 1] + spectrum[k].real();
    }
    spectrum = std::vector<std::complex<double>>();
    for (long k = 0; k <= half; ++k)
      power_[k] = Weight(k, half) * 4.0 * sine[k] * sine[k] / (2.0 * length_);
  }
  tan2_.resize(half + 1);
  for (long k = 0; k <= half; ++k) {
    const double t = std::tan(kPi * static_cast<double>(k) / length_);
    tan2_[k] = t * t;
  }
  tail_power_.assign(half + 2, 0.0);
  for (long k = half; k >= 0; --k) tail_power_[k] = tail_power_[k + 1] + power_[k];
}

double ButterworthGcv::Score(double cutoff_hz, double* trace, double* rss) const {
  const double kc = std::tan(kPi * cutoff_hz / sample_rate_hz_);
  const double inv = 1.0 / (kc * kc);
  // Above `ratio` x fc, |H|^2 < 1e-16 (order 4: 1 / (1 + 100^8); order 2: 1 / (1 + 1e4^4)); the
  // warping only makes it smaller. There the residual is the rest of the power.
  const double ratio = order_ == 4 ? 100.0 : 1e4;
  const auto last = static_cast<std::size_t>(
      std::min<double>(static_cast<double>(tan2_.size() - 1),
                       std::ceil(ratio * cutoff_hz / sample_rate_hz_ * length_)));
  double residual = tail_power_[last + 1], sum_h = 0.0;
  for (std::size_t k = 0; k <= last; ++k) {
    const double h = PowerResponse(order_, tan2_[k] * inv);
    residual += (1.0 - h) * (1.0 - h) * power_[k];
    sum_h += Weight(static_cast<long>(k), static_cast<long>(tan2_.size()) - 1) * h;
  }
  const double m = static_cast<double>(samples_);
  const double tr = sum_h * m / length_;
  if (trace) *trace = tr;
  if (rss) *rss = residual;
  return m * residual / ((m - tr) * (m - tr));
}

ButterworthResult ZeroPhaseButterworth(const Eigen::VectorXd& x, double sample_rate_hz,
                                       const ButterworthOptions& options) {
  ButterworthResult out;
  if (!options.IsValid(&out.message)) return out;
  const Eigen::Index n = x.size();
  if (n < 8) {
    out.termination = Termination::kInsufficientData;
    out.message = "butterworth: fewer than 8 samples";
    return out;
  }
  const double nyquist = 0.5 * sample_rate_hz;
  out.gcv = std::numeric_limits<double>::quiet_NaN();
  out.cutoff_hz = options.cutoff_hz;
  if (options.cutoff_hz > 0.0) {
    if (options.cutoff_hz >= nyquist) {
      out.message = "butterworth cutoff_hz must be below the Nyquist frequency";
      return out;
    }
  } else {
    const ButterworthGcv gcv(x, sample_rate_hz, options.order);
    const double lo = options.min_cycles * sample_rate_hz / static_cast<double>(n);
    const double hi = options.max_fraction_of_nyquist * nyquist;
    if (!(lo < hi)) {
      out.termination = Termination::kInsufficientData;
      out.message = "butterworth: record too short for the GCV cutoff range";
      return out;
    }
    const LogSearchResult best =
        MinimizeOnLogScale([&](double fc) { return gcv.Score(fc); }, lo, hi, options.grid_points,
                           options.relative_tolerance);
    out.cutoff_hz = best.argument;
    out.gcv = gcv.Score(out.cutoff_hz, &out.trace);
    out.at_lower_bound = best.at_lower_bound;
  }
  out.output =
      FilterForwardBackward(ButterworthSections(options.order, out.cutoff_hz, sample_rate_hz), x,
                            ButterworthPad(out.cutoff_hz, sample_rate_hz));
  out.termination = out.output.allFinite() ? Termination::kSuccess : Termination::kNumericalFailure;
  if (!HasResult(out.termination)) out.message = "butterworth: non-finite output";
  return out;
}

}  // namespace fogpipe::filters
