// The distribution of an overlapping Allan-variance estimate with few averages, for confidence
// bounds that do not rest on the chi-square approximation.
//
// s2(m) = sum_{i<M} D_i^2 / (c tau^2 M) is a quadratic form in the Gaussian differences D (second
// differences of the phase for OADEV, c = 2; third for OHDEV, c = 6),
// so s2 / E[s2] = sum_j mu_j chi2_1,j with mu the eigenvalues of D's M x M covariance, normalised
// to sum 1 (Imhof 1961). The chi-square law with the EDF 1 / sum mu^2 (Greenhall & Riley's EDF is
// exactly this) matches its first two moments only. With many averages the weights are many and
// nearly equal and the two laws agree; with fewer than 16 a few unequal weights dominate, and the
// chi-square 68.3 % interval is too wide: it covers the truth in 70-73 % of records of white and
// random-walk FM at 8 and 4 averages (docs/allan-statistics.md).
//
// For frequency noise (white FM N, flicker FM B, random-walk FM K) D_i is continuous in i, so the
// weights come from D's covariance sampled at K = 128 equally spaced starts (a Riemann sum of the
// integral operator; against the full M x M eigenvalues its quantiles agree to 2e-3 at 4-16
// averages, estimate_law_test), and the quantiles of sum mu_j chi2_1 from the Lugannani-Rice
// saddlepoint approximation of its distribution function (Kuonen 1999, Biometrika 86:929; one
// weight is chi-square(1) and is computed exactly). Against 2e6 simulated sums the saddlepoint's
// tail probabilities are within 0.006 at 4 averages and 0.002 at 8-16; both tails err the same
// way, so the 68.3 % interval's probability is within 0.002. White and flicker PM, whose D are
// not continuous in their start, have their own weights (phase_noise_law.h), with a remainder of
// many small weights summarised as one scaled chi-square.
#pragma once

#include <array>
#include <utility>
#include <vector>

namespace fogpipe::allan {

/// The law of sum_j mu_j chi2_1,j + bulk_mu chi2_{bulk_dof}, all terms independent: a few
/// weights mu (descending) and, optionally, a remainder of many small weights summarised by the
/// scaled chi-square with the same first two moments (bulk_dof real, >= 0). A plain list of
/// weights converts to it.
struct WeightedChiSquareLaw {
  std::vector<double> mu;
  double bulk_mu = 0.0;
  double bulk_dof = 0.0;

  WeightedChiSquareLaw() = default;
  // Implicit: a list of weights is a law without a remainder.
  WeightedChiSquareLaw(std::vector<double> weights) : mu(std::move(weights)) {}  // NOLINT
  bool empty() const { return mu.empty() && !(bulk_dof > 0.0 && bulk_mu > 0.0); }
};

/// With fewer averages than this (rate samples / m), OADEV and OHDEV bounds come from the
/// estimate's law (LawBounds) instead of chi-square, under the calibrated
/// noise-identification rule.
inline constexpr long long kLawBelowAverages = 16;

/// true when an overlapping d-th difference row at factor m with `count` differences
/// (count + d m - 1 rate samples; d = 2 OADEV, 3 OHDEV) has fewer than kLawBelowAverages
/// averages.
bool FewAverages(int d, long long m, long long count);

/// Normalised weights mu (sum 1, descending) of s2 / E[s2] for the overlapping d-th difference
/// variance at averaging factor m with `count` differences, for D's covariance
/// sum_k theta_k c_k (avar_covariance.h's DifferenceCovariance; theta = (ignored, N^2 t0,
/// B^2 t0^2, K^2 t0^3), any common scale). Empty when the row does not have FewAverages
/// (chi-square serves there) or the covariance is not positive.
std::vector<double> OverlappingLawWeights(int d, const std::array<double, 4>& theta, long long m,
                                          long long count);

/// P(law <= x) by the Lugannani-Rice saddlepoint approximation, mu > 0.
double WeightedChiSquareCdf(const WeightedChiSquareLaw& law, double x);

/// The p-quantile of the law, 0 < p < 1 (safeguarded Newton steps on WeightedChiSquareCdf with
/// the saddlepoint density, to 1e-9 relative; exact chi-square for one weight or the bulk alone).
double WeightedChiSquareQuantile(const WeightedChiSquareLaw& law, double p);

/// Two-sided bounds of a deviation sigma whose variance estimate is s2 = E[s2] law:
/// [sigma / sqrt(q_high), sigma / sqrt(q_low)], q the (1 +- confidence) / 2 quantiles.
void LawBounds(double sigma, const WeightedChiSquareLaw& law, double confidence, double* low,
               double* high);
/// One of those bounds from its quantile q of the law: sigma / sqrt(q).
double LawBound(double sigma, double quantile);

}  // namespace fogpipe::allan
