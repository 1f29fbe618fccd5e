#include "algorithms/allan/estimate_law.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/allan/avar_covariance.h"
#include "algorithms/common/chi_square.h"
#include "algorithms/common/units.h"

namespace fogpipe::allan {
namespace {

constexpr int kLawPoints = 128;
constexpr double kSqrt2Pi = 2.5066282746310002;

double NormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// Cumulant generating function of the law and its first two derivatives at t.
struct Cgf {
  double k0 = 0.0, k1 = 0.0, k2 = 0.0;
};
Cgf Evaluate(const WeightedChiSquareLaw& law, double t) {
  Cgf c;
  for (double w : law.mu) {
    const double d = 1.0 - 2.0 * w * t;
    c.k0 += -0.5 * std::log(d);
    c.k1 += w / d;
    c.k2 += 2.0 * w * w / (d * d);
  }
  if (law.bulk_dof > 0.0) {
    const double w = law.bulk_mu, d = 1.0 - 2.0 * w * t;
    c.k0 += -0.5 * law.bulk_dof * std::log(d);
    c.k1 += law.bulk_dof * w / d;
    c.k2 += law.bulk_dof * 2.0 * w * w / (d * d);
  }
  return c;
}

// The largest weight, which bounds the cumulant generating function's domain t < 1 / (2 max).
double MaxWeight(const WeightedChiSquareLaw& law) {
  double max_mu = law.bulk_dof > 0.0 ? law.bulk_mu : 0.0;
  for (double w : law.mu) max_mu = std::max(max_mu, w);
  return max_mu;
}

}  // namespace

bool FewAverages(int d, long long m, long long count) {
  return m >= 1 && count >= 1 && (count + d * m - 1) / m < kLawBelowAverages;
}

std::vector<double> OverlappingLawWeights(int d, const std::array<double, 4>& theta, long long m,
                                          long long count) {
  if ((d != 2 && d != 3) || !FewAverages(d, m, count)) return {};
  const int k = static_cast<int>(std::min<long long>(count, kLawPoints));
  const double step = static_cast<double>(count) / k;  // samples per point (1 when count <= K)
  std::vector<double> lag_covariance(static_cast<size_t>(k));
  for (int l = 0; l < k; ++l) {
    const std::array<double, 4> c = DifferenceCovariance(d, m, l * step);
    lag_covariance[static_cast<size_t>(l)] = theta[1] * c[1] + theta[2] * c[2] + theta[3] * c[3];
  }
  Eigen::MatrixXd cov(k, k);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) cov(i, j) = lag_covariance[static_cast<size_t>(std::abs(i - j))];
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov, Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) return {};
  double sum = 0.0;  // of the positive eigenvalues (rounding leaves tiny negative ones)
  for (int j = 0; j < k; ++j) sum += std::max(eig.eigenvalues()[j], 0.0);
  if (!(sum > 0.0)) return {};
  // Weights below 1e-12 of the total carry nothing measurable and only cost time.
  std::vector<double> out;
  for (int j = 0; j < k; ++j)
    if (eig.eigenvalues()[j] / sum > 1e-12) out.push_back(eig.eigenvalues()[j] / sum);
  std::sort(out.rbegin(), out.rend());
  return out;
}

namespace {

// The saddlepoint t of sum mu_j chi2_1 at x, K'(t) = x, and the cumulants there. K' increases
// from 0 to infinity on (-inf, 1 / (2 max mu)); Newton steps (K'' > 0) kept inside a shrinking
// bracket, bisection when a step leaves it.
Cgf Saddlepoint(const WeightedChiSquareLaw& mu, double x, double* t_out) {
  double hi = 0.5 / MaxWeight(mu), lo = -1.0;
  while (Evaluate(mu, lo).k1 > x) lo *= 2.0;
  double t = std::clamp(0.5 * (1.0 - 1.0 / x), lo, 0.5 * (lo + hi));  // exact for one weight 1
  Cgf c = Evaluate(mu, t);
  for (int it = 0; it < 100; ++it) {
    const double f = c.k1 - x;
    (f < 0.0 ? lo : hi) = t;
    double next = t - f / c.k2;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const bool done = std::abs(next - t) <= 1e-14 * std::max(1.0, std::abs(t));
    t = next;
    c = Evaluate(mu, t);
    if (done || hi - lo <= 1e-15 * std::max(1.0, std::abs(t))) break;
  }
  *t_out = t;
  return c;
}

}  // namespace

namespace {

// The Lugannani-Rice distribution function at x, and the saddlepoint density
// exp(K(t) - t x) / sqrt(2 pi K''(t)) from the same saddlepoint (the quantile's Newton steps need
// both).
struct SaddlepointAt {
  double cdf = 0.0, density = 0.0;
};
SaddlepointAt Approximate(const WeightedChiSquareLaw& mu, double x) {
  double mean = 0.0, k2 = 0.0, k3 = 0.0;
  for (double w : mu.mu) mean += w, k2 += 2.0 * w * w, k3 += 8.0 * w * w * w;
  if (mu.bulk_dof > 0.0) {
    const double w = mu.bulk_mu, nu = mu.bulk_dof;
    mean += nu * w, k2 += 2.0 * nu * w * w, k3 += 8.0 * nu * w * w * w;
  }
  // Near the mean the Lugannani-Rice terms cancel; their limit is 1/2 + skewness / (6 sqrt(2 pi)).
  const double skew_limit = 0.5 + k3 / (6.0 * kSqrt2Pi * std::pow(k2, 1.5));
  double t = 0.0;
  const Cgf c = Saddlepoint(mu, x, &t);
  const double density = std::exp(c.k0 - t * x) / std::sqrt(2.0 * units::kPi * c.k2);
  const double w2 = 2.0 * (t * x - c.k0);
  if (std::abs(x - mean) < 1e-9 * mean || std::abs(t) * std::sqrt(c.k2) < 1e-4 || !(w2 > 0.0))
    return {skew_limit, density};
  const double w = (t > 0.0 ? 1.0 : -1.0) * std::sqrt(w2);
  const double u = t * std::sqrt(c.k2);
  const double f = NormalCdf(w) + std::exp(-0.5 * w * w) / kSqrt2Pi * (1.0 / w - 1.0 / u);
  return {std::clamp(f, 0.0, 1.0), density};
}

}  // namespace

double WeightedChiSquareCdf(const WeightedChiSquareLaw& mu, double x) {
  if (!(x > 0.0)) return 0.0;
  if (mu.empty()) return std::numeric_limits<double>::quiet_NaN();
  return Approximate(mu, x).cdf;
}

double WeightedChiSquareQuantile(const WeightedChiSquareLaw& mu, double p) {
  if (!(p > 0.0 && p < 1.0) || mu.empty()) return std::numeric_limits<double>::quiet_NaN();
  // One weight is chi-square(1) exactly, where the saddlepoint is least accurate (0.012 in a
  // tail); the bulk alone is a scaled chi-square.
  const bool bulk = mu.bulk_dof > 0.0 && mu.bulk_mu > 0.0;
  if (mu.mu.size() == 1 && !bulk) return mu.mu[0] * stats::ChiSquareQuantile(p, 1.0);
  if (mu.mu.empty()) return mu.bulk_mu * stats::ChiSquareQuantile(p, mu.bulk_dof);
  double lo = 0.0, hi = 2.0;
  while (WeightedChiSquareCdf(mu, hi) < p) hi *= 2.0;
  // Newton on F(x) = p with the saddlepoint density, inside the bracket [lo, hi], bisection when
  // a step leaves it.
  double x = 0.5 * (lo + hi);
  for (int it = 0; it < 100 && hi - lo > 1e-9 * hi; ++it) {
    const SaddlepointAt s = Approximate(mu, x);
    const double f = s.cdf - p;
    (f < 0.0 ? lo : hi) = x;
    double next = s.density > 0.0 ? x - f / s.density : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-10 * x) return next;
    x = next;
  }
  return x;
}

void LawBounds(double sigma, const WeightedChiSquareLaw& mu, double confidence, double* low,
               double* high) {
  const double tail = 0.5 * (1.0 - confidence);
  *low = LawBound(sigma, WeightedChiSquareQuantile(mu, 1.0 - tail));
  *high = LawBound(sigma, WeightedChiSquareQuantile(mu, tail));
}

double LawBound(double sigma, double quantile) { return sigma / std::sqrt(quantile); }

}  // namespace fogpipe::allan
