#include "algorithms/allan/avar_covariance.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "algorithms/common/units.h"

namespace fogpipe::allan {
namespace {

constexpr int kQ = 0, kN = 1, kB = 2, kK = 3, kG = 4, kTerms = 5;
constexpr double kW[3] = {1.0, -2.0, 1.0};
// Integer lag ranges up to this length are summed exactly; longer ones by quadrature (whose error
// relative to the sum is O(1 / m^2) there, below 1e-4).
constexpr long long kExactLags = 96;
// Where the shorter difference spans fewer than kShortDifference samples, its knots (p ma - q mb)
// are that close together and the midpoint rule misses the kinks between them (m 1 against 90
// was 7 % off): the lags within kExactAroundKnots of every knot are then summed exactly, and only
// the smooth stretches between the knots' clusters are integrated.
constexpr long long kShortDifference = 32;
constexpr long long kExactAroundKnots = 16;
// 4-point Gauss-Legendre on [-1, 1].
constexpr double kGlX[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                            0.8611363115940526};
constexpr double kGlW[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                            0.3478548451374538};

// Lag sums of the Gauss-Markov term's tail (beyond the differences' support, where it decays as
// e^{-r |l|}) are summed over integer lags when it is this short, and integrated otherwise (the
// integral's error relative to the sum is then O(r^2 / 24) < 1e-4).
// The tail is taken over 25 Tc: beyond, c_G^2 is below e^-50 and c_G c_B below e^-25 of their
// values at the edge. Its panels are at most 2 Tc wide (4-point Gauss-Legendre on e^-x over
// [0, 4]: relative error ~1e-6).
constexpr double kGaussMarkovDecays = 25.0;
constexpr double kGaussMarkovPanelDecays = 2.0;
constexpr long long kExactTailLags = 512;

// e^-x - 1 + x - x^2 / 2 without cancellation: its Taylor series below x = 0.1 (the terms to
// x^9, truncation < 1e-17 relative), the closed form above.
double ExpRemainder(double x) {
  if (x < 0.1) {
    double term = -x * x * x / 6.0, sum = term;
    for (int k = 4; k <= 9; ++k) sum += (term *= -x / k);
    return sum;
  }
  return std::exp(-x) - 1.0 + x - 0.5 * x * x;
}

// w times the generalised autocovariances of the phase at lag u (file comment) of N, B, K and,
// with r = t0 / Tc > 0, the Gauss-Markov term in the form -ExpRemainder(r |u|) / r^2 (the file
// comment's law less a constant and an even quadratic, which the differences annihilate; with
// them it would cancel catastrophically for r |u| << 1).
void AddAutocovariance(double u, double w, double r, double c[kTerms]) {
  const double a = std::abs(u);
  c[kN] += w * (-0.5 * a);
  c[kK] += w * (a * a * a / 12.0);
  if (a > 0.0) c[kB] += w * (u * u * std::log(a) / (2.0 * units::kPi));
  if (r > 0.0) c[kG] += w * (-ExpRemainder(r * a) / (r * r));
}

// Lag sums in sample units (t0 = 1), before normalisation.
struct Sums {
  double s[kTerms][kTerms] = {};
  double h[kTerms] = {};
  void Add(double weight, const double c[kTerms]) {
    for (int k = 0; k < kTerms; ++k) {
      h[k] += weight * c[k];
      for (int l = k; l < kTerms; ++l) s[k][l] += weight * c[k] * c[l];
    }
  }
};

struct Pair {
  long long ma, mb, count_a, count_b;
  double r = 0.0;  // t0 / Tc of the Gauss-Markov term, 0 without one
  // Number of (i, j) pairs, i < Ma, j < Mb, with j - i = l (continuous l: the same piecewise
  // linear function).
  double Count(double l) const {
    const double hi = std::min(static_cast<double>(count_a), static_cast<double>(count_b) - l);
    const double lo = std::max(0.0, -l);
    return std::max(0.0, hi - lo);
  }
  // c_k(l) for N, B, K, G (Q left 0: it lives on integer knots only).
  void Continuous(double l, double c[kTerms]) const {
    for (int k = 0; k < kTerms; ++k) c[k] = 0.0;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q)
        AddAutocovariance(l + static_cast<double>(q * mb - p * ma), kW[p] * kW[q], r, c);
    if (r > 0.0 && (l >= 2.0 * ma || l <= -2.0 * mb)) c[kG] = GaussMarkovOutside(l);
  }
  // Beyond the support every lag u has one sign and the nine exponentials factor:
  // c_G = -e^{-r (|l| - 2 m_near)} expm1(-r ma)^2 expm1(-r mb)^2 / r^2, m_near = ma for l > 0 and
  // mb for l < 0 (the sum form loses all digits there when r |l| is large).
  double GaussMarkovOutside(double l) const {
    const double edge = l > 0 ? 2.0 * ma : 2.0 * mb;
    const double ea = std::expm1(-r * ma), eb = std::expm1(-r * mb);
    return -std::exp(-r * (std::abs(l) - edge)) * ea * ea * eb * eb / (r * r);
  }
  // White-PM coefficient at an integer lag: the weights of coinciding phase samples.
  double WhitePm(long long l) const {
    double c = 0.0;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q)
        if (l + q * mb - p * ma == 0) c += kW[p] * kW[q];
    return c;
  }
  void Exact(long long l, double c[kTerms]) const {
    Continuous(static_cast<double>(l), c);
    c[kQ] = WhitePm(l);
  }
};

void GaussLegendre(const Pair& pair, double x0, double x1, Sums* sums) {
  const double mid = 0.5 * (x0 + x1), half = 0.5 * (x1 - x0);
  double c[kTerms];
  for (int g = 0; g < 4; ++g) {
    const double l = mid + half * kGlX[g];
    const double n = pair.Count(l);
    if (n <= 0.0) continue;
    pair.Continuous(l, c);
    sums->Add(half * kGlW[g] * n, c);
  }
}

// One piece between knots, split geometrically towards both ends: next to a knot the flicker
// kernel carries a logarithm (of the distance to the other knots, a min(ma, mb) away), and the
// Gauss-Markov kernel an exponential of scale Tc / t0 = 1 / r, which one 4-point rule over a long
// piece misses.
void GradedPiece(const Pair& pair, double a, double b, Sums* sums) {
  double h0 = 0.5 * static_cast<double>(std::max(1LL, std::min(pair.ma, pair.mb)));
  if (pair.r > 0.0) h0 = std::min(h0, 0.5 / pair.r);
  const double mid = 0.5 * (a + b);
  double x = a, step = h0;
  std::vector<double> left = {a}, right = {b};
  while (x + step < mid) x += step, step *= 3.0, left.push_back(x);
  x = b, step = h0;
  while (x - step > mid) x -= step, step *= 3.0, right.push_back(x);
  left.insert(left.end(), right.rbegin(), right.rend());
  for (size_t k = 0; k + 1 < left.size(); ++k) GaussLegendre(pair, left[k], left[k + 1], sums);
}

// The lags beyond the support from x0 outwards (direction +1 or -1) to the end of the count range,
// where only flicker and the Gauss-Markov term remain.
void FlickerTail(const Pair& pair, double x0, double direction, Sums* sums);

void Tail(const Pair& pair, long long first_lag, double direction, Sums* sums) {
  const long long end = direction > 0 ? pair.count_b - 1 : -(pair.count_a - 1);
  double x0 = first_lag - 0.5 * direction;
  if (pair.r > 0.0) {
    // The Gauss-Markov part: over kGaussMarkovDecays correlation times, summed exactly where that
    // is short and otherwise on doubling panels no wider than kGaussMarkovPanelDecays Tc.
    const double extent = kGaussMarkovDecays / pair.r;
    double c[kTerms];
    if (extent <= kExactTailLags) {
      const long long steps = static_cast<long long>(std::ceil(extent));
      long long l = first_lag;
      for (long long k = 0; k < steps && (end - l) * direction >= 0;
           ++k, l += (direction > 0 ? 1 : -1)) {
        pair.Exact(l, c);
        sums->Add(pair.Count(static_cast<double>(l)), c);
      }
      x0 = l - 0.5 * direction;
    } else {
      const double stop =
          direction > 0 ? std::min(x0 + extent, end + 0.5) : std::max(x0 - extent, end - 0.5);
      const double widest = kGaussMarkovPanelDecays / pair.r;
      double step = std::min(static_cast<double>(std::max(pair.ma, pair.mb)), widest);
      while ((stop - x0) * direction > 0.0) {
        double x1 = x0 + direction * step;
        if ((x1 - stop) * direction > 0.0) x1 = stop;
        GaussLegendre(pair, std::min(x0, x1), std::max(x0, x1), sums);
        x0 = x1;
        step = std::min(2.0 * step, widest);
      }
    }
  }
  FlickerTail(pair, x0, direction, sums);
}

void FlickerTail(const Pair& pair, double x0, double direction, Sums* sums) {
  const double end =
      direction > 0 ? static_cast<double>(pair.count_b) : -static_cast<double>(pair.count_a);
  if ((end - x0) * direction <= 0.0) return;
  const double width = static_cast<double>(std::max(pair.ma, pair.mb));
  double a = x0;
  for (int k = 1; k <= 4; ++k) {
    double b = x0 + direction * width * (std::pow(2.0, k) - 1.0);
    if ((b - end) * direction >= 0.0) b = end;
    GaussLegendre(pair, std::min(a, b), std::max(a, b), sums);
    a = b;
    if (a == end) return;
  }
  // Far tail: c_B ~ -A / l^2 with A = ma^2 mb^2 / pi (the fourth difference of l^2 ln|l| / 2 pi);
  // the count is taken constant at its value at the start (it decreases linearly, so this is an
  // upper bound on a term that is already < 1e-4 of the total).
  const double big_a =
      static_cast<double>(pair.ma * pair.ma) * static_cast<double>(pair.mb * pair.mb) / units::kPi;
  const double l0 = std::abs(a), l1 = std::abs(end), n0 = pair.Count(a);
  sums->s[kB][kB] += n0 * big_a * big_a / 3.0 * (1.0 / (l0 * l0 * l0) - 1.0 / (l1 * l1 * l1));
  sums->h[kB] += -n0 * big_a * (1.0 / l0 - 1.0 / l1);
}

Sums LagSums(const Pair& pair) {
  Sums sums;
  const long long lo = std::max(-2 * pair.mb, -(pair.count_a - 1));
  const long long hi = std::min(2 * pair.ma, pair.count_b - 1);
  if (hi < lo) return sums;
  double c[kTerms];
  if (hi - lo + 1 <= kExactLags) {
    for (long long l = lo; l <= hi; ++l) {
      pair.Exact(l, c);
      sums.Add(pair.Count(static_cast<double>(l)), c);
    }
  } else {
    // Sum over integers ~ integral over [lo - 1/2, hi + 1/2] (midpoint rule), split at the knots.
    std::vector<double> knots = {lo - 0.5, hi + 0.5, 0.0,
                                 static_cast<double>(pair.count_b - pair.count_a)};
    std::vector<long long> integer_knots;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) {
        const long long l = p * pair.ma - q * pair.mb;
        knots.push_back(static_cast<double>(l));
        integer_knots.push_back(l);
      }
    std::sort(knots.begin(), knots.end());
    std::sort(integer_knots.begin(), integer_knots.end());
    integer_knots.erase(std::unique(integer_knots.begin(), integer_knots.end()),
                        integer_knots.end());
    // The lag ranges summed exactly (merged, in order), and the stretches between them
    // (midpoint rule: lag l stands for [l - 1/2, l + 1/2]) integrated piece by piece.
    std::vector<std::pair<long long, long long>> exact;
    if (std::min(pair.ma, pair.mb) < kShortDifference) {
      for (long long k : integer_knots) {
        const long long from = std::max(lo, k - kExactAroundKnots);
        const long long to = std::min(hi, k + kExactAroundKnots);
        if (from > to) continue;
        if (!exact.empty() && from <= exact.back().second + 1)
          exact.back().second = std::max(exact.back().second, to);
        else
          exact.push_back({from, to});
      }
    }
    std::vector<std::pair<double, double>> stretches;
    double start = lo - 0.5;
    for (const auto& [from, to] : exact) {
      if (from - 0.5 > start) stretches.push_back({start, from - 0.5});
      start = to + 0.5;
    }
    if (hi + 0.5 > start) stretches.push_back({start, hi + 0.5});
    for (const auto& [x0, x1] : stretches)
      for (size_t k = 0; k + 1 < knots.size(); ++k) {
        const double a = std::max(knots[k], x0), b = std::min(knots[k + 1], x1);
        if (b > a) GradedPiece(pair, a, b, &sums);
      }
    for (const auto& [from, to] : exact)
      for (long long l = from; l <= to; ++l) {
        pair.Exact(l, c);
        sums.Add(pair.Count(static_cast<double>(l)), c);
      }
    // White PM: exact contributions at the integer knots outside those ranges (each lag once).
    const auto summed = [&exact](long long l) {
      for (const auto& [from, to] : exact)
        if (l >= from && l <= to) return true;
      return false;
    };
    for (long long l : integer_knots) {
      if (l < lo || l > hi || summed(l)) continue;
      pair.Exact(l, c);
      const double n = pair.Count(static_cast<double>(l));
      sums.s[kQ][kQ] += n * c[kQ] * c[kQ];
      for (int k = kN; k < kTerms; ++k) sums.s[kQ][k] += n * c[kQ] * c[k];
      sums.h[kQ] += n * c[kQ];
    }
  }
  // Beyond the support only flicker remains. Where the number of differences ends the lag range
  // first there is no lag beyond it: a tail there would add fractional lags of every term (a
  // single difference then read white FM's EDF as 0.8 instead of 1).
  if (hi == 2 * pair.ma) Tail(pair, hi + 1, +1.0, &sums);
  if (lo == -2 * pair.mb) Tail(pair, lo - 1, -1.0, &sums);
  return sums;
}

// Normalised coefficients for one pair: t0 powers 0, 1, 2, 3, 2 for Q, N, B, K, G.
void Normalise(const Pair& pair, const Sums& sums, double t0, std::array<double, 15>* s,
               std::array<double, 5>* h) {
  constexpr int kPower[kTerms] = {0, 1, 2, 3, 2};
  const double tau_a = pair.ma * t0, tau_b = pair.mb * t0;
  const double mm = static_cast<double>(pair.count_a) * static_cast<double>(pair.count_b);
  const double gauss = 2.0 / (4.0 * tau_a * tau_a * tau_b * tau_b * mm);
  int idx = 0;
  for (int k = 0; k < kTerms; ++k) {
    (*h)[k] = std::pow(t0, kPower[k]) * sums.h[k] / mm;
    for (int l = k; l < kTerms; ++l)
      (*s)[idx++] = gauss * std::pow(t0, kPower[k] + kPower[l]) * sums.s[k][l];
  }
}

double Evaluate(const std::array<double, 15>& s, const std::array<double, 5>& h,
                const std::array<double, 4>& theta, double r2, double gm_sigma2) {
  const double t[kTerms] = {theta[0], theta[1], theta[2], theta[3], gm_sigma2};
  double v = 0.0;
  int idx = 0;
  for (int k = 0; k < kTerms; ++k) {
    v += r2 * t[k] * h[k];
    for (int l = k; l < kTerms; ++l) v += (k == l ? 1.0 : 2.0) * t[k] * t[l] * s[idx++];
  }
  return v;
}

// t0 / Tc, 0 without a Gauss-Markov term.
double DecayPerSample(double sample_period_s, double correlation_time_s) {
  return correlation_time_s > 0.0 ? sample_period_s / correlation_time_s : 0.0;
}

}  // namespace

std::array<double, 4> DifferenceCovariance(int d, long long m, double lag) {
  // The difference's weights on phase samples m apart: 1, -2, 1 or 1, -3, 3, -1.
  constexpr double kW3[4] = {1.0, -3.0, 3.0, -1.0};
  const double* w = d == 2 ? kW : kW3;
  double c[kTerms] = {};
  if (d != 2 && d != 3) return {};
  for (int p = 0; p <= d; ++p)
    for (int q = 0; q <= d; ++q)
      AddAutocovariance(lag + static_cast<double>((q - p) * m), w[p] * w[q], 0.0, c);
  return {c[kQ], c[kN], c[kB], c[kK]};
}

double GaussMarkovDifferenceCovariance(long long ma, long long mb, double lag,
                                       double correlation_samples) {
  Pair pair{ma, mb, 1, 1};
  pair.r = 1.0 / correlation_samples;
  double c[kTerms];
  pair.Continuous(lag, c);
  return c[kG];
}

AvarCovarianceModel::AvarCovarianceModel(const std::vector<long long>& m,
                                         const std::vector<long long>& count,
                                         double sample_period_s, double gm_correlation_time_s)
    : rows_(static_cast<int>(m.size())) {
  const double r = DecayPerSample(sample_period_s, gm_correlation_time_s);
  s_.resize(static_cast<size_t>(rows_) * (rows_ + 1) / 2);
  h_.resize(s_.size());
  size_t idx = 0;
  for (int a = 0; a < rows_; ++a)
    for (int b = a; b < rows_; ++b, ++idx) {
      const Pair pair{m[a], m[b], count[a], count[b], r};
      Normalise(pair, LagSums(pair), sample_period_s, &s_[idx], &h_[idx]);
    }
}

Eigen::MatrixXd AvarCovarianceModel::Covariance(const std::array<double, 4>& theta, double r2,
                                                double gm_sigma2) const {
  Eigen::MatrixXd c(rows_, rows_);
  size_t idx = 0;
  for (int a = 0; a < rows_; ++a)
    for (int b = a; b < rows_; ++b, ++idx)
      c(a, b) = c(b, a) = Evaluate(s_[idx], h_[idx], theta, r2, gm_sigma2);
  return c;
}

std::shared_ptr<const AvarCovarianceModel> SharedAvarCovarianceModel(
    const std::vector<long long>& m, const std::vector<long long>& count, double sample_period_s) {
  struct Entry {
    std::vector<long long> m, count;
    double sample_period_s = 0.0;
    std::shared_ptr<const AvarCovarianceModel> model;
  };
  constexpr size_t kKept = 4;
  thread_local std::vector<Entry> kept;  // most recently used last
  for (auto it = kept.begin(); it != kept.end(); ++it) {
    if (it->m != m || it->count != count || it->sample_period_s != sample_period_s) continue;
    Entry hit = std::move(*it);
    kept.erase(it);
    kept.push_back(std::move(hit));
    return kept.back().model;
  }
  if (kept.size() == kKept) kept.erase(kept.begin());
  kept.push_back({m, count, sample_period_s,
                  std::make_shared<const AvarCovarianceModel>(m, count, sample_period_s)});
  return kept.back().model;
}

double AvarCovarianceBySum(long long ma, long long mb, long long count_a, long long count_b,
                           double sample_period_s, const std::array<double, 4>& theta, double r2,
                           double gm_sigma2, double gm_correlation_time_s) {
  const Pair pair{ma, mb, count_a, count_b, DecayPerSample(sample_period_s, gm_correlation_time_s)};
  Sums sums;
  double c[kTerms];
  for (long long l = -(count_a - 1); l <= count_b - 1; ++l) {
    pair.Exact(l, c);
    sums.Add(pair.Count(static_cast<double>(l)), c);
  }
  std::array<double, 15> s;
  std::array<double, 5> h;
  Normalise(pair, sums, sample_period_s, &s, &h);
  return Evaluate(s, h, theta, r2, gm_sigma2);
}

}  // namespace fogpipe::allan
