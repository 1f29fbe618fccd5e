#include "algorithms/filters/butterworth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/filters/search.h"

namespace fogpipe::filters {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Runs one section over v in place, forward or backward, started in the steady state of its
/// first input (unity DC gain: output = input = u, so z2 = (b2 - a2) u, z1 = (1 - b0) u).
void RunSection(const Biquad& s, Eigen::VectorXd* v, bool forward) {
  const Eigen::Index n = v->size();
  double* d = v->data();
  const double u = forward ? d[0] : d[n - 1];
  double z1 = (1.0 - s.b0) * u, z2 = (s.b2 - s.a2) * u;
  for (Eigen::Index i = 0; i < n; ++i) {
    double& x = d[forward ? i : n - 1 - i];
    const double y = s.b0 * x + z1;
    z1 = s.b1 * x - s.a1 * y + z2;
    z2 = s.b2 * x - s.a2 * y;
    x = y;
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
  const Eigen::Index n = x.size();
  if (n < 2) return x;
  const Eigen::Index pad = std::clamp<Eigen::Index>(pad_samples, 1, n - 1);
  // Odd reflection about both end samples.
  Eigen::VectorXd ext(n + 2 * pad);
  for (Eigen::Index i = 0; i < pad; ++i) {
    ext[i] = 2.0 * x[0] - x[pad - i];
    ext[n + pad + i] = 2.0 * x[n - 1] - x[n - 2 - i];
  }
  ext.segment(pad, n) = x;
  for (const Biquad& s : sections) RunSection(s, &ext, true);
  for (const Biquad& s : sections) RunSection(s, &ext, false);
  return ext.segment(pad, n);
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

double ZeroPhaseButterworthTrace(int order, double cutoff_hz, double sample_rate_hz,
                                 Eigen::Index n) {
  // Bins above 100 fc (and their mirror images) have |H|^2 < 1e-16 for order 2 and 4.
  const double nn = static_cast<double>(n);
  const auto last = static_cast<Eigen::Index>(
      std::min(0.5 * nn, std::ceil(100.0 * cutoff_hz / sample_rate_hz * nn)));
  const double kc = std::tan(kPi * cutoff_hz / sample_rate_hz);
  const double inv = 1.0 / (kc * kc);
  double trace = 1.0;  // k = 0
  for (Eigen::Index k = 1; k <= last; ++k) {
    const double t = std::tan(kPi * static_cast<double>(k) / nn);
    const double h = PowerResponse(order, t * t * inv);
    trace += (2 * k == n) ? h : 2.0 * h;  // bins k and n - k
  }
  return trace;
}

Eigen::Index ButterworthPad(double cutoff_hz, double sample_rate_hz) {
  return static_cast<Eigen::Index>(std::ceil(8.0 * sample_rate_hz / cutoff_hz));
}

ButterworthGcv::ButterworthGcv(const Eigen::VectorXd& x, double sample_rate_hz, int order)
    : x_(x), sample_rate_hz_(sample_rate_hz), order_(order) {}

double ButterworthGcv::Score(double cutoff_hz, double* trace) const {
  const Eigen::VectorXd y = FilterForwardBackward(
      ButterworthSections(order_, cutoff_hz, sample_rate_hz_), x_,
      ButterworthPad(cutoff_hz, sample_rate_hz_));
  const double rss = (x_ - y).squaredNorm();
  const double tr = ZeroPhaseButterworthTrace(order_, cutoff_hz, sample_rate_hz_, x_.size());
  if (trace) *trace = tr;
  const double n = static_cast<double>(x_.size());
  return n * rss / ((n - tr) * (n - tr));
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
  out.output = FilterForwardBackward(
      ButterworthSections(options.order, out.cutoff_hz, sample_rate_hz), x,
      ButterworthPad(out.cutoff_hz, sample_rate_hz));
  out.termination = out.output.allFinite() ? Termination::kSuccess : Termination::kNumericalFailure;
  if (!HasResult(out.termination)) out.message = "butterworth: non-finite output";
  return out;
}

}  // namespace fogpipe::filters
