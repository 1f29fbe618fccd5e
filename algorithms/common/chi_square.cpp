#include "algorithms/common/chi_square.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace fogpipe::stats {
namespace {

constexpr double kEps = 1e-16;
constexpr double kTiny = 1e-300;

// Loader (2000), "Fast and accurate computation of binomial probabilities", eq. (5)-(6): the
// deviance term bd0(a, x) = a ln(a / x) + x - a, by its series in v = (a - x) / (a + x) where the
// direct form would cancel. Loader switches at |v| = 0.1; up to |v| = 0.5 the series still
// converges in under 30 terms, and beyond it bd0 > 0.43 a, so the direct form's rounding,
// ~1e-16 a, is a small part of an exponent whose probability is below e^-0.43a.
double Bd0(double a, double x) {
  if (std::abs(a - x) < 0.5 * (a + x)) {
    double v = (a - x) / (a + x);
    double sum = (a - x) * v;
    double term = 2.0 * a * v;
    v *= v;
    for (int j = 1; j < 1000; ++j) {
      term *= v;
      const double next = sum + term / (2 * j + 1);
      if (next == sum) return next;
      sum = next;
    }
    return sum;
  }
  return a * std::log(a / x) + x - a;
}

// Loader (2000), section 2: ln Gamma(a + 1) - ln(sqrt(2 pi a) (a / e)^a), by its asymptotic series
// above a = 15 (the terms of Abramowitz & Stegun 6.1.40), from lgamma below.
double StirlingError(double a) {
  constexpr double kS0 = 1.0 / 12, kS1 = 1.0 / 360, kS2 = 1.0 / 1260, kS3 = 1.0 / 1680,
                   kS4 = 1.0 / 1188;
  constexpr double kLnSqrt2Pi = 0.918938533204672741780329736406;
  if (a <= 15.0) return std::lgamma(a + 1.0) - (a + 0.5) * std::log(a) + a - kLnSqrt2Pi;
  const double aa = a * a;
  if (a > 500) return (kS0 - kS1 / aa) / a;
  if (a > 80) return (kS0 - (kS1 - kS2 / aa) / aa) / a;
  if (a > 35) return (kS0 - (kS1 - (kS2 - kS3 / aa) / aa) / aa) / a;
  return (kS0 - (kS1 - (kS2 - (kS3 - kS4 / aa) / aa) / aa) / aa) / a;
}

// x^a e^-x / Gamma(a) = sqrt(a / (2 pi)) exp(-bd0(a, x) - StirlingError(a)). Written as
// exp(a ln x - x - lgamma(a)) its exponent is a difference of terms of size a ln a, whose rounding
// alone is a relative error of ~1e-16 a ln a (1e-9 at a = 5e5); in this form the exponent is
// computed to a relative error of a few ulps.
double GammaPrefactor(double a, double x) {
  constexpr double kTwoPi = 6.283185307179586476925286766559;
  return std::sqrt(a / kTwoPi) * std::exp(-Bd0(a, x) - StirlingError(a));
}

// Series gamma(a, x) / Gamma(a) = x^a e^-x / Gamma(a + 1) * sum_k x^k / ((a + 1)...(a + k)).
double GammaPSeries(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int k = 1; k < 10000; ++k) {
    term *= x / (a + k);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEps) break;
  }
  return sum * GammaPrefactor(a, x);
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
  return GammaPrefactor(a, x) * h;
}

}  // namespace

double RegularizedGammaP(double a, double x) {
  if (!(a > 0.0) || !(x >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return 0.0;
  if (x < a + 1.0) return GammaPSeries(a, x);
  return 1.0 - GammaQContinuedFraction(a, x);
}

double RegularizedGammaQ(double a, double x) {
  if (!(a > 0.0) || !(x >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return 1.0;
  if (x < a + 1.0) return 1.0 - GammaPSeries(a, x);
  return GammaQContinuedFraction(a, x);
}

double ChiSquareCdf(double x, double dof) { return RegularizedGammaP(0.5 * dof, 0.5 * x); }

double ChiSquareSurvival(double x, double dof) { return RegularizedGammaQ(0.5 * dof, 0.5 * x); }

namespace {

// The quantiles asked for repeat: the same confidence levels at the same equivalent degrees of
// freedom (an Allan table's taus have the same edf in every signal of one record with the same
// noise types, and a sweep scores 110 such signals). A small per-thread table keyed by the exact
// bits of (p, dof) returns a value computed before; the function is pure, so the numbers do not
// depend on hits, threads or order.
struct QuantileMemo {
  static constexpr std::size_t kSize = 512;
  struct Entry {
    double p = 0.0, dof = -1.0, value = 0.0;
  };
  Entry entries[kSize];
  static std::size_t Slot(double p, double dof) {
    std::uint64_t a, b;
    std::memcpy(&a, &p, sizeof(a));
    std::memcpy(&b, &dof, sizeof(b));
    const std::uint64_t h = (a ^ (b * 0x9E3779B97F4A7C15ull)) * 0xBF58476D1CE4E5B9ull;
    return static_cast<std::size_t>(h >> 55) % kSize;
  }
};

double ComputeChiSquareQuantile(double p, double dof) {
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
  // Chi-square(dof) is sub-gamma with variance factor 2 dof and scale 2, so
  // P(X >= dof + 2 sqrt(dof t) + 2 t) <= e^-t (Laurent & Massart 2000, Lemma 1; Boucheron, Lugosi
  // & Massart 2013, section 2.4): with t = -ln(1 - p), an hi beyond that bound has F(hi) >= p and
  // the CDF, a sum of about sqrt(36 dof) terms at large dof, need not be evaluated there.
  const double tail = -std::log1p(-p);
  const double bound = dof + 2.0 * std::sqrt(dof * tail) + 2.0 * tail;
  if (!(hi > bound))
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

}  // namespace

double ChiSquareQuantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  thread_local QuantileMemo memo;
  QuantileMemo::Entry& entry = memo.entries[QuantileMemo::Slot(p, dof)];
  if (entry.p == p && entry.dof == dof) return entry.value;
  entry = {p, dof, ComputeChiSquareQuantile(p, dof)};
  return entry.value;
}

}  // namespace fogpipe::stats
