#include "algorithms/allan/edf.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fogpipe::allan {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kJmax = 100;

// Greenhall & Riley eq. (7): the generalized autocovariance kernel of power-law phase noise.
// A common sign per alpha is irrelevant: only squares of linear combinations are used.
double Sw(double t, int alpha) {
  const double a = std::abs(t);
  switch (alpha) {
    case 2:
      return -a;
    case 1:
      return a == 0.0 ? 0.0 : t * t * std::log(a);
    case 0:
      return a * a * a;
    case -1:
      return a == 0.0 ? 0.0 : -t * t * t * t * std::log(a);
    case -2:
      return a * a * a * a * a;
    case -3:
      return a == 0.0 ? 0.0 : t * t * t * t * t * t * std::log(a);
    case -4:
      return a * a * a * a * a * a * a;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Eq. (8): the kernel seen through the averaging filter with factor F (F = infinity: alpha + 2).
double Sx(double t, double f, int alpha) {
  if (std::isinf(f)) return Sw(t, alpha + 2);
  return f * f * (2.0 * Sw(t, alpha) - Sw(t - 1.0 / f, alpha) - Sw(t + 1.0 / f, alpha));
}

// Eq. (9): through the d-th difference, sum_k (-1)^k C(2d, d + k) sx(t + k), k = -d..d.
double Sz(double t, double f, int alpha, int d) {
  double binom = 1.0;  // C(2d, 0)
  double sum = 0.0;
  for (int j = 0; j <= 2 * d; ++j) {  // j = d + k
    const int k = j - d;
    sum += ((k % 2 == 0) ? 1.0 : -1.0) * binom * Sx(t + k, f, alpha);
    binom = binom * (2 * d - j) / (j + 1);
  }
  return sum;
}

// Eq. (10): the basic sum.
double BasicSum(double j_terms, double big_m, double s, double f, int alpha, int d) {
  const double sz0 = Sz(0.0, f, alpha, d);
  double sum = sz0 * sz0;
  const long long jj = static_cast<long long>(j_terms);
  for (long long j = 1; j < jj; ++j) {
    const double z = Sz(j / s, f, alpha, d);
    sum += 2.0 * (1.0 - j / big_m) * z * z;
  }
  const double zj = Sz(j_terms / s, f, alpha, d);
  return sum + (1.0 - j_terms / big_m) * zj * zj;
}

// Inverse EDF from the basic sum with J terms, normalized by sz(0)^2 M.
double InverseEdfFromSum(double j_terms, double big_m, double s, double f, int alpha, int d,
                         double sum_f) {
  const double sz0 = Sz(0.0, sum_f, alpha, d);
  return BasicSum(j_terms, big_m, s, f, alpha, d) / (sz0 * sz0 * big_m);
}

// Table 2 (unmodified variances, alpha <= 2): {a0, a1} for d = 1, 2, 3; rows alpha = 2 .. -4.
// Entries that the paper leaves empty (alpha + 2d <= 1) are NaN.
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTable2[7][3][2] = {
    {{3.0 / 2.0, 1.0 / 2.0}, {35.0 / 18.0, 1.0}, {231.0 / 100.0, 3.0 / 2.0}},  // alpha = 2
    {{78.6, 25.2}, {790.0, 410.0}, {9950.0, 6520.0}},                          // alpha = 1
    {{2.0 / 3.0, 1.0 / 6.0}, {2.0 / 3.0, 1.0 / 3.0}, {7.0 / 9.0, 1.0 / 2.0}},  // alpha = 0
    {{kNaN, kNaN}, {0.852, 0.375}, {0.997, 0.617}},                            // alpha = -1
    {{kNaN, kNaN}, {1.079, 0.368}, {1.033, 0.607}},                            // alpha = -2
    {{kNaN, kNaN}, {kNaN, kNaN}, {1.053, 0.553}},                              // alpha = -3
    {{kNaN, kNaN}, {kNaN, kNaN}, {1.302, 0.535}},                              // alpha = -4
};
// Table 1 (modified variances, F = 1): {a0, a1} for d = 1, 2, 3; rows alpha = 2 .. -4.
constexpr double kTable1[7][3][2] = {
    {{2.0 / 3.0, 1.0 / 3.0}, {7.0 / 9.0, 1.0 / 2.0}, {22.0 / 25.0, 2.0 / 3.0}},  // alpha = 2
    {{0.840, 0.345}, {0.997, 0.616}, {1.141, 0.843}},                            // alpha = 1
    {{1.079, 0.368}, {1.033, 0.607}, {1.184, 0.848}},                            // alpha = 0
    {{kNaN, kNaN}, {1.048, 0.534}, {1.180, 0.816}},                              // alpha = -1
    {{kNaN, kNaN}, {1.302, 0.535}, {1.175, 0.777}},                              // alpha = -2
    {{kNaN, kNaN}, {kNaN, kNaN}, {1.194, 0.703}},                                // alpha = -3
    {{kNaN, kNaN}, {kNaN, kNaN}, {1.489, 0.702}},                                // alpha = -4
};
// Table 3 (alpha = 1): {b0, b1} for d = 1, 2, 3.
constexpr double kTable3[3][2] = {{6.0, 4.0}, {15.23, 12.0}, {47.8, 40.0}};

double BinomialCoefficient(int n, int k) {
  double c = 1.0;
  for (int i = 1; i <= k; ++i) c = c * (n - k + i) / i;
  return c;
}

}  // namespace

double GreenhallEdf(int alpha, int d, long long m, long long n_phase, bool overlapping,
                    bool sampled_phase) {
  if (d < 1 || d > 3 || alpha > 2 || alpha < -4 || alpha + 2 * d <= 1 || m < 1) return kNaN;
  const double f = static_cast<double>(m);  // unmodified variance: F = m
  const double s = overlapping ? static_cast<double>(m) : 1.0;
  const double l = 1.0 + static_cast<double>(m) * d;  // filter length m / F + m d
  const double big_m = 1.0 + std::floor(s * (static_cast<double>(n_phase) - l) / m);
  if (big_m < 1.0) return kNaN;
  const double j = std::min(big_m, (d + 1) * s);
  const double r = big_m / s;
  const double* t2 = kTable2[2 - alpha][d - 1];
  double inv_edf = kNaN;
  if (alpha <= 0) {
    if (j <= kJmax) {
      const bool case_a = !sampled_phase && static_cast<double>(m) * (d + 1) <= kJmax;
      const double mp = case_a ? f : kInf;  // case 2.1a / b
      inv_edf = InverseEdfFromSum(j, big_m, s, mp, alpha, d, mp);
    } else if (r > d + 1) {
      inv_edf = (t2[0] - t2[1] / r) / r;  // case 2.2
    } else {
      const double mp = kJmax / r;  // case 2.3
      inv_edf = InverseEdfFromSum(kJmax, kJmax, mp, kInf, alpha, d, kInf);
    }
  } else if (alpha == 1) {
    const double b = kTable3[d - 1][0] + kTable3[d - 1][1] * std::log(static_cast<double>(m));
    if (j <= kJmax) {
      inv_edf = InverseEdfFromSum(j, big_m, s, f, 1, d, f);  // case 3.1
    } else if (r > d + 1) {
      inv_edf = (t2[0] - t2[1] / r) / (b * b * r);  // case 3.2
    } else {
      const double mp = kJmax / r;  // case 3.3
      inv_edf = BasicSum(kJmax, kJmax, mp, mp, 1, d) / (b * b * kJmax);
    }
  } else {  // alpha == 2
    const double k = std::ceil(r);
    if (k <= d) {
      // Few terms: the exact basic sum (J = M here since M <= d S).
      inv_edf = InverseEdfFromSum(big_m, big_m, s, f, 2, d, f);
    } else {
      const double a0 = BinomialCoefficient(4 * d, 2 * d) /
                        (BinomialCoefficient(2 * d, d) * BinomialCoefficient(2 * d, d));
      const double a1 = d / 2.0;
      inv_edf = (a0 - a1 / r) / big_m;  // case 4.2
    }
  }
  if (!(inv_edf > 0.0)) return kNaN;
  return 1.0 / inv_edf;
}

double GreenhallModifiedEdf(int alpha, int d, long long m, long long n_phase) {
  if (d < 1 || d > 3 || alpha > 2 || alpha < -4 || alpha + 2 * d <= 1 || m < 1) return kNaN;
  const double s = static_cast<double>(m);            // overlapping: S = m
  const double l = static_cast<double>(m) * (1 + d);  // filter length m / F + m d, F = 1
  const double big_m = 1.0 + std::floor(s * (static_cast<double>(n_phase) - l) / m);
  if (big_m < 1.0) return kNaN;
  const double j = std::min(big_m, (d + 1) * s);
  const double r = big_m / s;
  double inv_edf = kNaN;
  if (j <= kJmax) {
    inv_edf = InverseEdfFromSum(j, big_m, s, 1.0, alpha, d, 1.0);  // case 1.1
  } else if (r > d + 1) {
    const double* t1 = kTable1[2 - alpha][d - 1];
    inv_edf = (t1[0] - t1[1] / r) / r;  // case 1.2
  } else {
    inv_edf = InverseEdfFromSum(kJmax, kJmax, kJmax / r, 1.0, alpha, d, 1.0);  // case 1.3
  }
  if (!(inv_edf > 0.0)) return kNaN;
  return 1.0 / inv_edf;
}

double TotalVarianceEdf(int alpha, long long m, long long n_rate_samples) {
  if (m < 1 || m > MaxAveragingFactor(Deviation::kTotal, n_rate_samples)) return kNaN;
  const double ratio = static_cast<double>(n_rate_samples) / static_cast<double>(m);  // T / tau
  const double big_n = static_cast<double>(n_rate_samples + 1);
  const double mm = static_cast<double>(m);
  double edf = kNaN;
  switch (alpha) {
    case 2:
      edf = (big_n + 1.0) * (big_n - 2.0 * mm) / (2.0 * (big_n - mm));
      break;
    case 1:
      edf = std::exp(std::sqrt(std::log((big_n - 1.0) / (2.0 * mm)) *
                               std::log((2.0 * mm + 1.0) * (big_n - 1.0) / 4.0)));
      break;
    case 0:
      edf = 1.50 * ratio;
      break;
    case -1:
      edf = 1.17 * ratio - 0.22;
      break;
    case -2:
      edf = 0.93 * ratio - 0.36;
      break;
  }
  return edf > 0.0 ? edf : kNaN;
}

double DeviationEdf(Deviation deviation, int alpha, long long m, long long n_rate_samples,
                    bool sampled_phase) {
  if (deviation == Deviation::kTotal) return TotalVarianceEdf(alpha, m, n_rate_samples);
  const int d = DifferenceOrder(deviation);
  if (IsModified(deviation)) return GreenhallModifiedEdf(alpha, d, m, n_rate_samples + 1);
  return GreenhallEdf(alpha, d, m, n_rate_samples + 1, IsOverlapping(deviation), sampled_phase);
}

}  // namespace fogpipe::allan
