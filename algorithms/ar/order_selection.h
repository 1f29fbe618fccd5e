// Models of every order 1..P from one order-recursive pass, and order selection by BIC.
//
// BIC convention (Schwarz 1978), the same N for every order:
//   BIC(p) = N ln(sigma_p^2) + p ln(N),
// sigma_p^2 the estimator's innovation variance at order p and N the number of samples that the
// estimator's residuals cover (all N samples for Burg and Yule-Walker; N - P for least squares,
// which conditions every order on the same first P samples so the orders stay comparable). Why a
// common N and not N_eff = N - p: with N - p the criterion gains a term -p ln(sigma_p^2), which
// depends on the units of x (rescaling x from rad/s to deg/h would shift the selected order). The
// mean is removed before fitting and counts as one parameter for every order, so it does not change
// the argmin and is left out. The order with the smallest BIC is selected (ties: the lower order).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

namespace fogpipe::ar {

/// The result of one order-recursive estimator run.
struct OrderSequence {
  /// phi[p - 1]: recursion coefficients of the order-p model, p = 1..orders_completed.
  std::vector<Eigen::VectorXd> phi;
  /// innovation_variance(p - 1): the estimator's sigma_p^2, p = 1..orders_completed.
  Eigen::VectorXd innovation_variance;
  /// reflection(m - 1) = kappa_m, m = 1..orders_completed, for the lattice estimators (Burg,
  /// Yule-Walker), where |kappa_m| < 1 holds exactly; empty for least squares.
  Eigen::VectorXd reflection;
  /// N in the BIC (see the file comment).
  Eigen::Index num_effective = 0;
  /// Orders actually produced. Fewer than asked when the prediction error vanished (a noise-free
  /// signal is exactly predictable at some order: higher orders are undefined).
  int orders_completed = 0;
};

/// BIC(p) for p = 1..innovation_variance.size(); entry p - 1. +inf where sigma_p^2 <= 0.
Eigen::VectorXd Bic(const Eigen::VectorXd& innovation_variance, Eigen::Index num_effective);

/// The order (1-based) with the smallest BIC; the lower order on ties. 0 for an empty vector.
int SelectOrderByBic(const Eigen::VectorXd& bic);

/// The order to run: an AR model is only filtered or simulated if it is stationary as stored
/// (stationarity.h), because an explosive model's Kalman filter and free run diverge.
///   requested == 0 (order by BIC): the smallest BIC among the orders q with stationary(q); ties
///     the lower order.
///   requested > 0 (a fixed order): the highest q <= requested with stationary(q).
/// Orders 1..bic.size() are considered; stationary(q) is asked lazily (best candidates first).
/// When no order qualifies, BIC's own order or `requested` is returned, and the caller reports the
/// model as not stationary.
int SelectStationaryOrder(const Eigen::VectorXd& bic, int requested,
                          const std::function<bool(int)>& stationary);

}  // namespace fogpipe::ar
