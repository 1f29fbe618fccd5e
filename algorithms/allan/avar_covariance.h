// Covariance matrix of overlapping Allan-variance estimates at several averaging factors, for a
// Gaussian rate process made of the IEEE Std 952 noise terms (white angle Q, white rate N, flicker
// rate B, random-walk rate K), optionally a first-order Gauss-Markov rate (sigma, Tc), plus a
// deterministic ramp R. It is what a generalised-least-squares
// fit of the terms needs: neighbouring Allan points share data and are strongly correlated.
//
// With phase (angle) samples x_k [rad] at interval t0, D_i(m) = x_{i+2m} - 2 x_{i+m} + x_i and
// s2(m) = sum_{i<M} D_i^2 / (2 tau^2 M), tau = m t0. For Gaussian D (Isserlis),
//   Cov(s2(ma), s2(mb)) = sum_i sum_j [2 c_ij^2 + 4 mu_a mu_b c_ij] / (4 tau_a^2 tau_b^2 Ma Mb),
// c_ij = Cov(D_i(ma), D_j(mb)) = sum_{p,q in 0,1,2} w_p w_q Rx(j - i + q mb - p ma), w = (1,-2,1),
// and mu = R tau^2 the mean of D under the ramp. Rx is the generalised autocovariance of the phase
// (defined up to an even quadratic, which second differences annihilate; Greenhall & Riley 2003,
// eq. 7, and Greenhall 1992), per unit amplitude^2 and in sample lags u:
//   Q (white PM):   delta(u)                     N (white FM):   -|u| t0 / 2
//   B (flicker FM): u^2 ln|u| t0^2 / (2 pi)       K (RW FM):      |u|^3 t0^3 / 12
//   G (Gauss-Markov rate, autocovariance sigma^2 e^{-|t|/Tc}, per unit sigma^2):
//                   -(Tc |u| t0 + Tc^2 e^{-|u| t0 / Tc})
// (each reproduces its IEEE Allan variance 3Q^2/tau^2, N^2/tau, (2 ln2/pi) B^2, K^2 tau/3 and,
// for G, (2 sigma^2 Tc / tau) [1 - Tc / (2 tau) (3 - 4 e^{-tau/Tc} + e^{-2 tau/Tc})], the law of
// IEEE Std 952-1997 Annex C and NIST SP 1065 with q^2 = 2 sigma^2 / Tc). G's follows from the
// angle's structure function E[(x(t+u) - x(t))^2] = 2 sigma^2 (Tc |u| - Tc^2 (1 - e^{-|u|/Tc})),
// the double integral of the rate's autocovariance, of which Rx is -1/2 (up to a constant). The
// angle is the integral of the continuous rate, as in a gyro that outputs angle increments; a
// record of point samples of the rate differs by O(t0 / Tc). c_ij
// depends only on the lag l = j - i, so the double sum is sum_l count(l) c(l)^2 with count(l) the
// number of (i, j) pairs at that lag. c(l) is piecewise smooth between the knots l = p ma - q mb
// (polynomial for N and K), so it is summed exactly over integer lags when the lag range is short
// and otherwise integrated by 4-point Gauss-Legendre between knots (exact for the piecewise
// polynomials of N and K; the white-PM deltas at the knots are added exactly). Outside the
// support [-2 mb, 2 ma] only flicker, c ~ -ma^2 mb^2 / (pi l^2), and Gauss-Markov, c ~ e^{-|l| t0 /
// Tc} (the differences do not overlap but the rate is correlated over Tc), remain; that tail is
// summed or integrated over 25 Tc, then integrated on doubling panels and in closed form.
//
// The covariance is quadratic in theta = (Q^2, N^2, B^2, K^2, sigma^2) and linear in R^2 theta,
// so the lag sums are done once per table (and Tc) and the matrix for any amplitudes costs
// O(points^2).
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

namespace fogpipe::allan {

/// Lag sums for every pair of rows (a <= b), independent of the noise amplitudes.
class AvarCovarianceModel {
 public:
  /// m: averaging factors; count: number of overlapping differences M = n + 1 - 2m per row;
  /// sample_period_s: t0; gm_correlation_time_s: Tc of the Gauss-Markov term (0: none, and
  /// Covariance's gm_sigma2 is ignored). Rows need not be sorted.
  AvarCovarianceModel(const std::vector<long long>& m, const std::vector<long long>& count,
                      double sample_period_s, double gm_correlation_time_s = 0.0);

  /// Cov(s2_a, s2_b) [(rad/s)^4] for theta = (Q^2 [rad^2], N^2 [rad^2/s], B^2 [rad^2/s^2],
  /// K^2 [rad^2/s^3]), the ramp r2 = R^2 [rad^2/s^4] and the Gauss-Markov variance gm_sigma2 =
  /// sigma^2 [rad^2/s^2].
  Eigen::MatrixXd Covariance(const std::array<double, 4>& theta, double r2,
                             double gm_sigma2 = 0.0) const;

  int size() const { return rows_; }

 private:
  int rows_ = 0;
  // Per pair (a <= b, packed row-major upper triangle): S_kl = 2 sum count c_k c_l /
  // (4 tau_a^2 tau_b^2 Ma Mb) with the t0 powers folded in (15 entries, k <= l, terms Q, N, B, K,
  // G), and H_k = sum count c_k / (Ma Mb) for the ramp interaction.
  std::vector<std::array<double, 15>> s_;
  std::vector<std::array<double, 5>> h_;
};

/// The model for (m, count, sample_period_s), as constructed, shared with the callers that asked
/// for the same rows: the last few models built on the calling thread are kept. Building one
/// costs more than the fit that uses it, and a parameter sweep fits hundreds of tables of one
/// record length, whose rows repeat.
std::shared_ptr<const AvarCovarianceModel> SharedAvarCovarianceModel(
    const std::vector<long long>& m, const std::vector<long long>& count, double sample_period_s);

/// c_k(l) = Cov(D_i(m), D_{i+l}(m)) per unit theta_k with t0 = 1 for the d-th difference of the
/// phase at lag m (d = 2 Allan: weights 1, -2, 1; d = 3 Hadamard: 1, -3, 3, -1), for the
/// frequency noises N (k = 1), B (2) and K (3) at any real lag l [samples]; element 0 (white PM,
/// which lives on integer knots only) is 0. Multiply by theta_k t0^k for the covariance in rad^2.
/// All zero for any other d.
std::array<double, 4> DifferenceCovariance(int d, long long m, double lag);

/// Cov(D_i(ma), D_{i+l}(mb)) of the Allan (second) differences of the angle for a unit-variance
/// Gauss-Markov rate with correlation time `correlation_samples` = Tc / t0, with t0 = 1 and l =
/// `lag` [samples]; multiply by sigma^2 t0^2 for rad^2.
double GaussMarkovDifferenceCovariance(long long ma, long long mb, double lag,
                                       double correlation_samples);

/// Reference: the same covariance for one pair by the explicit sum over every integer lag (slow
/// for large m; for tests).
double AvarCovarianceBySum(long long ma, long long mb, long long count_a, long long count_b,
                           double sample_period_s, const std::array<double, 4>& theta, double r2,
                           double gm_sigma2 = 0.0, double gm_correlation_time_s = 0.0);

}  // namespace fogpipe::allan
