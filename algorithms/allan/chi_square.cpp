#include "algorithms/allan/chi_square.h"

#include <cmath>
#include <limits>

namespace fogpipe::allan {
namespace {

constexpr double kEps = 1e-16;
constexpr double kTiny = 1e-300;

// Series gamma(a, x) / Gamma(a) = x^a e^-x / Gamma(a + 1) * sum_k x^k / ((a + 1)...(a + k)).
double GammaPSeries(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int k = 1; k < 10000; ++k) {
    term *= x / (a + k);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEps) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Continued fraction for Q(a, x) by the modified Lentz method.
double GammaQContinuedFraction(double a, double x) {
  double b = x + 1.0 - a, c = 1.0 / kTiny, dd = 1.0 / b, h = dd;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    dd = an * dd + b;
    if (std::abs(dd) < kTiny) dd = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    dd = 1.0 / dd;
    const double delta = dd * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEps) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double RegularizedGammaP(double a, double x) {
  if (!(a > 0.0) || !(x >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return 0.0;
  if (x < a + 1.0) return GammaPSeries(a, x);
  return 1.0 - GammaQContinuedFraction(a, x);
}

double ChiSquareCdf(double x, double dof) { return RegularizedGammaP(0.5 * dof, 0.5 * x); }

double ChiSquareQuantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  // Wilson & Hilferty (1931) start: chi2 ~ dof (1 - 2/(9 dof) + z sqrt(2/(9 dof)))^3, z from an
  // approximate normal quantile (Abramowitz & Stegun 26.2.23, |error| < 4.5e-4); Newton refines.
  const double pp = p < 0.5 ? p : 1.0 - p;
  const double t = std::sqrt(-2.0 * std::log(pp));
  double z = t - (2.515517 + 0.802853 * t + 0.010328 * t * t) /
                     (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t);
  if (p < 0.5) z = -z;
  const double h = 2.0 / (9.0 * dof);
  double x = dof * std::pow(std::max(1.0 - h + z * std::sqrt(h), 1e-3), 3);
  // Bracket [lo, hi] with F(lo) < p < F(hi); Newton steps that leave it are replaced by bisection.
  double lo = 0.0, hi = std::max(2.0 * x, dof + 10.0 * std::sqrt(2.0 * dof) + 10.0);
  while (ChiSquareCdf(hi, dof) < p) hi *= 2.0;
  const double a = 0.5 * dof;
  for (int iter = 0; iter < 200; ++iter) {
    const double f = ChiSquareCdf(x, dof) - p;
    if (f < 0.0)
      lo = x;
    else
      hi = x;
    // Density of chi-square: x^(a-1) e^(-x/2) / (2^a Gamma(a)).
    const double log_pdf = (a - 1.0) * std::log(x) - 0.5 * x - a * std::log(2.0) - std::lgamma(a);
    double next = x - f / std::exp(log_pdf);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-14 * x || hi - lo <= 1e-14 * hi) return next;
    x = next;
  }
  return x;
}

}  // namespace fogpipe::allan
