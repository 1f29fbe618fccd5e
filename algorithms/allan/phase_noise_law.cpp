#include "algorithms/allan/phase_noise_law.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/common/units.h"

namespace fogpipe::allan {
namespace {

constexpr int kBlocks = 128;
// Lags within this distance of a spike (or of the range's ends) are summed one by one. Between
// them the covariance is smooth on the scale of its distance to the nearest spike, so the sum is
// the integral over the unit cells (with the Euler-Maclaurin end correction), by Gauss-Legendre
// on panels that double in width away from the spikes.
constexpr long long kExactNearKnot = 16;
// 8-point Gauss-Legendre on [-1, 1].
constexpr double kGlX[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                            -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                            0.7966664774136267,  0.9602898564975363};
constexpr double kGlW[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                            0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                            0.2223810344533745, 0.1012285362903763};
// psi(1/2) = -gamma - 2 ln 2.
constexpr double kDigammaHalf = -1.9635100260214235;

// The digamma function for x >= 1/2: the recurrence up to x >= 10, then the asymptotic series
// (Abramowitz & Stegun 6.3.18), whose first omitted term is below 1e-15 there.
double Digamma(double x) {
  double shift = 0.0;
  while (x < 10.0) shift -= 1.0 / x, x += 1.0;
  const double r = 1.0 / (x * x);
  return shift + std::log(x) - 0.5 / x -
         r * (1.0 / 12.0 - r * (1.0 / 120.0 - r * (1.0 / 252.0 - r * (1.0 / 240.0 - r / 132.0))));
}

// E (x_u - x_0)^2 of flicker PM per unit level (file comment of the header).
double FlickerStructure(double u) {
  if (u == 0.0) return 0.0;
  return 2.0 / units::kPi * (Digamma(std::abs(u) + 0.5) - kDigammaHalf);
}

// The d-th difference at lag m of one phase-noise type.
class PhaseDifference {
 public:
  PhaseDifference(int d, int alpha, long long m) : alpha_(alpha), m_(m) {
    weights_ =
        d == 2 ? std::vector<double>{1.0, -2.0, 1.0} : std::vector<double>{1.0, -3.0, 3.0, -1.0};
  }
  int order() const { return static_cast<int>(weights_.size()) - 1; }
  bool smooth_part() const { return alpha_ == 1; }
  // The spikes' lags: k m, |k| <= d.
  std::vector<long long> Knots() const {
    std::vector<long long> out;
    for (int k = -order(); k <= order(); ++k) out.push_back(k * m_);
    return out;
  }
  // c(l) at an integer lag.
  double Exact(long long lag) const {
    if (alpha_ == 1) return Smooth(static_cast<double>(lag));  // V(0) = 0: no spike of its own
    return Combine(static_cast<double>(lag), [](double u) { return u == 0.0 ? 1.0 : 0.0; });
  }
  // c(x) away from the spikes, at a real lag (flicker PM; white PM has nothing there).
  double Smooth(double lag) const {
    if (alpha_ == 2) return 0.0;
    return Combine(lag, [](double u) { return -0.5 * FlickerStructure(u); });
  }

 private:
  // sum_{p,q} w_p w_q Rx(lag + (q - p) m) for the phase's generalised autocovariance Rx.
  template <class Rx>
  double Combine(double lag, const Rx& rx) const {
    double c = 0.0;
    for (size_t p = 0; p < weights_.size(); ++p)
      for (size_t q = 0; q < weights_.size(); ++q) {
        const long long shift = (static_cast<long long>(q) - static_cast<long long>(p)) * m_;
        c += weights_[p] * weights_[q] * rx(lag + static_cast<double>(shift));
      }
    return c;
  }

  int alpha_;
  long long m_;
  std::vector<double> weights_;
};

// The integral of f over [x0, x1] on panels that start at width kExactNearKnot at both ends and
// double towards the middle (f may have a logarithmic cusp just beyond either end).
template <class F>
double GradedIntegral(const F& f, double x0, double x1) {
  std::vector<double> left = {x0}, right = {x1};
  const double mid = 0.5 * (x0 + x1);
  double step = static_cast<double>(kExactNearKnot);
  for (double x = x0; x + step < mid; step *= 2.0) left.push_back(x += step);
  step = static_cast<double>(kExactNearKnot);
  for (double x = x1; x - step > mid; step *= 2.0) right.push_back(x -= step);
  left.insert(left.end(), right.rbegin(), right.rend());
  double sum = 0.0;
  for (size_t k = 0; k + 1 < left.size(); ++k) {
    const double c = 0.5 * (left[k] + left[k + 1]), h = 0.5 * (left[k + 1] - left[k]);
    for (int g = 0; g < 8; ++g) sum += h * kGlW[g] * f(c + h * kGlX[g]);
  }
  return sum;
}

// sum_{l = lo}^{hi} f(l) for f smooth between the anchors (spikes, kinks): exactly within
// kExactNearKnot of an anchor or of the ends, elsewhere as the integral over the unit cells
// [a - 1/2, b + 1/2] minus the Euler-Maclaurin term (f'(b + 1/2) - f'(a - 1/2)) / 24.
template <class Exact, class Smooth>
double SumOverLags(long long lo, long long hi, std::vector<long long> anchors, bool smooth_part,
                   const Exact& exact, const Smooth& smooth) {
  anchors.push_back(lo);
  anchors.push_back(hi);
  std::sort(anchors.begin(), anchors.end());
  double sum = 0.0;
  long long next = lo;  // the first lag not yet summed
  for (long long a : anchors) {
    if (a < lo || a > hi) continue;
    const long long from = std::max(next, a - kExactNearKnot),
                    to = std::min(hi, a + kExactNearKnot);
    if (from > next && smooth_part) {
      const double x0 = static_cast<double>(next) - 0.5, x1 = static_cast<double>(from) - 0.5;
      const auto derivative = [&](double x) { return (smooth(x + 0.25) - smooth(x - 0.25)) * 2.0; };
      sum += GradedIntegral(smooth, x0, x1) - (derivative(x1) - derivative(x0)) / 24.0;
    }
    for (long long l = from; l <= to; ++l) sum += exact(l);
    next = std::max(next, to + 1);
  }
  return sum;
}

// tr C = count c(0) and tr C^2 = sum_l (count - |l|) c(l)^2 (to about 1e-8 relative: the next
// Euler-Maclaurin term and the widest Gauss-Legendre panels).
void Traces(const PhaseDifference& diff, long long count, double* trace, double* trace_sq) {
  const double c0 = diff.Exact(0), n = static_cast<double>(count);
  *trace = n * c0;
  *trace_sq = n * c0 * c0 + 2.0 * SumOverLags(
                                      1, count - 1, diff.Knots(), diff.smooth_part(),
                                      [&](long long l) {
                                        const double c = diff.Exact(l);
                                        return static_cast<double>(count - l) * c * c;
                                      },
                                      [&](double x) {
                                        const double c = diff.Smooth(x);
                                        return (n - x) * c * c;
                                      });
}

}  // namespace

double PhaseNoiseDifferenceCovariance(int d, int alpha, long long m, long long lag) {
  if ((d != 2 && d != 3) || (alpha != 1 && alpha != 2) || m < 1) return 0.0;
  return PhaseDifference(d, alpha, m).Exact(lag);
}

double PhaseNoiseEdf(int d, int alpha, long long m, long long count) {
  if ((d != 2 && d != 3) || (alpha != 1 && alpha != 2) || m < 1 || count < 1)
    return std::numeric_limits<double>::quiet_NaN();
  double trace = 0.0, trace_sq = 0.0;
  Traces(PhaseDifference(d, alpha, m), count, &trace, &trace_sq);
  return trace * trace / trace_sq;
}

WeightedChiSquareLaw PhaseNoiseLaw(int d, int alpha, long long m, long long count) {
  if ((d != 2 && d != 3) || (alpha != 1 && alpha != 2) || !FewAverages(d, m, count)) return {};
  const PhaseDifference diff(d, alpha, m);
  // At most kBlocks blocks of b starts; the count - blocks b < b starts left over (under 1 %) are
  // part of the remainder.
  const long long b = (count + kBlocks - 1) / kBlocks, blocks = count / b;
  // T(k) = sum over the starts of two blocks k apart of c(j - i) = sum_l (b - |l|) c(k b + l).
  Eigen::MatrixXd compressed(blocks, blocks);
  std::vector<double> block_sum(static_cast<size_t>(blocks));
  for (long long k = 0; k < blocks; ++k) {
    std::vector<long long> anchors = {0};
    for (long long knot : diff.Knots()) anchors.push_back(knot - k * b);
    const double bd = static_cast<double>(b);
    block_sum[static_cast<size_t>(k)] = SumOverLags(
        -(b - 1), b - 1, anchors, diff.smooth_part(),
        [&](long long l) { return static_cast<double>(b - std::abs(l)) * diff.Exact(k * b + l); },
        [&](double x) { return (bd - std::abs(x)) * diff.Smooth(static_cast<double>(k * b) + x); });
  }
  for (long long i = 0; i < blocks; ++i)
    for (long long j = 0; j < blocks; ++j)
      compressed(i, j) = block_sum[static_cast<size_t>(std::abs(i - j))] / static_cast<double>(b);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(compressed, Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) return {};

  double trace = 0.0, trace_sq = 0.0;
  Traces(diff, count, &trace, &trace_sq);
  if (!(trace > 0.0) || !(trace_sq > 0.0)) return {};

  WeightedChiSquareLaw law;
  double ritz = 0.0, ritz_sq = 0.0;
  for (Eigen::Index j = 0; j < eig.eigenvalues().size(); ++j) {
    const double r = eig.eigenvalues()[j];
    if (!(r > 1e-12 * trace)) continue;  // carry nothing measurable; rounding leaves some < 0
    law.mu.push_back(r / trace);
    ritz += r, ritz_sq += r * r;
  }
  std::sort(law.mu.rbegin(), law.mu.rend());
  // The remainder keeps its mean exactly. Its spread tr C^2 - sum r^2 is known to tr C^2's own
  // accuracy only (1e-8), so it is floored there: a remainder that small is a near-constant shift,
  // never a large weight with few degrees of freedom.
  const double rest = trace - ritz, rest_sq = std::max(trace_sq - ritz_sq, 1e-8 * trace_sq);
  if (rest > 1e-6 * trace) {
    law.bulk_dof = rest * rest / rest_sq;
    law.bulk_mu = rest_sq / rest / trace;
  }
  return law;
}

}  // namespace fogpipe::allan
