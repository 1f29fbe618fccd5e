// A random-walk rate model, its Kalman filter and RTS smoother, with q and R by maximum
// likelihood (the local-level model of Harvey 1989, ch. 3; Durbin & Koopman 2012, ch. 2):
//
//   x_k = x_{k-1} + w_k,  w_k ~ N(0, q)     (the true rate wanders)
//   y_k = x_k + v_k,      v_k ~ N(0, R)     (white measurement noise)
//
// The first state is diffuse: after y_0 the filter holds x = y_0 with variance R, the exact
// diffuse start of the local-level model. With the ratio lambda = q / R fixed, every innovation
// variance is R f_k (f_k from the recursion with R = 1), so R has the closed-form maximiser
// R(lambda) = (1 / (N - 1)) sum_k e_k^2 / f_k and the profile log-likelihood is
//   l(lambda) = -(N - 1) / 2 log R(lambda) - 1/2 sum_k log f_k + const,
// maximised by the one-dimensional search of search.h over log lambda. The gain converges
// geometrically (rate 1 - K); once f_k stops changing in double precision the loop keeps the
// constant gain, which makes an evaluation a multiply-add per sample.
// The smoother is the fixed-interval RTS smoother (Rauch, Tung & Striebel 1965); for this model it
// equals the minimiser of sum (y_k - x_k)^2 / R + sum (x_k - x_{k-1})^2 / q (a tridiagonal
// least-squares problem), which the tests use as the independent reference.
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/common/status.h"

namespace fogpipe::filters {

struct RandomWalkKalmanOptions {
  /// Process-noise variance q and measurement-noise variance R, (units of x)^2 per sample; both
  /// < 0 (default): by maximum likelihood. Give both or neither.
  double q = -1.0;
  double r = -1.0;
  /// ML search of lambda = q / R over [min_ratio_times_n2 / N^2, max_ratio]: below the lower end
  /// the rate moves by less than a tenth of the noise over the whole record (constant).
  double min_ratio_times_n2 = 1e-2;
  double max_ratio = 1e2;
  int grid_points = 20;
  double relative_tolerance = 1e-2;

  bool IsValid(std::string* error) const;
};

struct RandomWalkKalmanResult {
  Eigen::VectorXd filtered;     ///< causal filter estimate x_{k|k}, units of x
  Eigen::VectorXd smoothed;     ///< RTS estimate x_{k|N}, units of x
  double q = 0.0;               ///< (units of x)^2 per sample
  double r = 0.0;               ///< (units of x)^2
  double log_likelihood = 0.0;  ///< profile log-likelihood at q / R (constant dropped)
  bool at_lower_bound = false;  ///< ML chose the smallest ratio of its grid (near-constant rate)
  Termination termination = Termination::kInvalidOptions;
  std::string message;
};

/// The profile log-likelihood l(lambda) of the header (constant dropped) and, optionally, the
/// R that maximises it at that lambda. x needs >= 2 samples.
double RandomWalkProfileLikelihood(const Eigen::VectorXd& x, double ratio, double* r_hat = nullptr);

/// RandomWalkProfileLikelihood at `count` ratios, values[i] for ratios[i], bit for bit: the
/// recursions of up to four ratios walk the data together (each waits on its own division, so
/// four of them overlap where one would stall).
void RandomWalkProfileLikelihoods(const Eigen::VectorXd& x, const double* ratios, int count,
                                  double* values);

/// -2 log-likelihood of y under the local-level model with KNOWN measurement variance r (> 0) and
/// walk variance q (>= 0), from the diffuse start of the header (x = y_0 with variance r): the
/// prediction-error decomposition sum_{k >= 1} (log F_k + e_k^2 / F_k) (Harvey 1989, ch. 3; Durbin
/// & Koopman 2012, 2.10.1), without the constant (N - 1) log(2 pi). The innovations and F_k / r are
/// those of the profile likelihood at lambda = q / r, so both come from one recursion. y needs
/// >= 2 samples.
double RandomWalkMinusTwoLogLikelihood(const Eigen::VectorXd& y, double q, double r);

struct WalkVarianceFit {
  /// The minimising walk variance, (units of y)^2 per sample; exactly 0 where q = 0 wins.
  double q = 0.0;
  double minus_two_log_likelihood = 0.0;  ///< RandomWalkMinusTwoLogLikelihood at q
  bool at_upper_bound = false;            ///< the best grid point was max_ratio (q may be larger)
};

/// RandomWalkMinusTwoLogLikelihood minimised over q >= 0 for known r (> 0): q = 0 (the constant
/// level, where the maximum likelihood piles up for a short or quiet record; Shephard & Harvey
/// 1990) against the search of search.h over log(q / r) in [min_ratio, max_ratio]
/// (0 < min_ratio < max_ratio), the grid's passes walking the data together (as
/// RandomWalkProfileLikelihoods). The grid has 8 points per decade, and the golden section stops
/// at a bracket narrower than a factor 1.001 in q: near the minimum -2 ln L moves by the square
/// of that step, far below any penalty it is compared with. The default range spans from a walk
/// far below the noise of any record to one that rules every sample. y needs >= 2 samples.
WalkVarianceFit MinimizeRandomWalkMinusTwoLogLikelihood(const Eigen::VectorXd& y, double r,
                                                        double min_ratio = 1e-6,
                                                        double max_ratio = 1e2);

/// Filter and smoother for given q, R (> 0).
void RandomWalkFilterSmoother(const Eigen::VectorXd& x, double q, double r,
                              Eigen::VectorXd* filtered, Eigen::VectorXd* smoothed);

RandomWalkKalmanResult RandomWalkKalman(const Eigen::VectorXd& x,
                                        const RandomWalkKalmanOptions& options);

}  // namespace fogpipe::filters
