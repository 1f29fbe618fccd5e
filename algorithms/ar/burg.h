// Burg's method (Burg 1975; Kay & Marple 1981, sec. V.B): every order 1..P in one recursion.
//
// At each order m the reflection coefficient minimises the summed forward and backward prediction
// error energy,
//   kappa_m = 2 sum f_{m-1}(n) b_{m-1}(n-1) / sum (f_{m-1}(n)^2 + b_{m-1}(n-1)^2),
// so |kappa_m| <= 1 by Cauchy-Schwarz and every Burg model is stationary (up to rounding when a
// root sits on the unit circle). The errors are then updated in place. Unlike the normal equations,
// no autocovariance matrix is formed or solved, which is why Burg stays accurate on the slow IMFs
// whose p x p autocovariance matrix has condition ~1e12 (see the tests).
//
// Innovation variance: sigma_0^2 = mean(x^2), sigma_m^2 = sigma_{m-1}^2 (1 - kappa_m^2) (Kay &
// Marple 1981, eq. 97), the estimate MATLAB's arburg reports.
//
// Cost: one fused pass per order: the error update of order m and the sums that give kappa_{m+1}
// run over the same cache-sized block, so each order streams the two N-double error arrays once.
// Memory: 2 N doubles.
#pragma once

#include <Eigen/Core>

#include "algorithms/ar/order_selection.h"

namespace fogpipe::ar {

/// The two error arrays of BurgAllOrders. A caller that fits many series of one length keeps one
/// and passes it to every call: fresh pages cost more than a pass of the recursion on the machines
/// fogpipe runs on (docs/performance.md), and a kept array of the right size is reused as it is.
struct BurgWork {
  Eigen::VectorXd forward;
  Eigen::VectorXd backward;
};

/// Burg models of orders 1..max_order of x - mean (pass the mean of x, or 0 for a series whose
/// mean is already removed; subtracting it here saves the caller an N-double copy).
/// num_effective = N. Stops early (orders_completed < max_order) if the prediction error vanishes.
/// `work` (may be null: the arrays are then allocated here) holds the error arrays; the results do
/// not depend on what it held before.
OrderSequence BurgAllOrders(const Eigen::Ref<const Eigen::VectorXd>& x, int max_order,
                            double mean = 0.0, BurgWork* work = nullptr);

/// The same estimator computed from the autocorrelation, after Vos (2013, "A fast implementation
/// of Burg's method"): one O(N P) pass for c(0..P), then each order's error energies are quadratic
/// forms in the (m+2) x (m+2) matrix of lagged products over the order's sample range, i.e.
/// c(|i-j|) minus head and tail corrections of at most m products each, O(P^4) in total for all
/// orders. Faster (one pass instead of P), but the energies come out as differences of terms of
/// size N gamma(0), so it loses about log10(gamma(0) / sigma^2) digits, ~8 on the paper's imf6
/// model (gamma(0) / sigma^2 = 2e8). Measured against a long-double Burg on imf6 at 1e7 samples
/// (burg_test.cpp): worst coefficient error over orders 1..20 of 0.42 standard errors (plain
/// recursion: 2e-9). FitAr therefore uses BurgAllOrders; this form is kept for that comparison.
/// Requires N > 2 max_order + 1.
OrderSequence BurgAllOrdersFromAutocorrelation(const Eigen::Ref<const Eigen::VectorXd>& x_centered,
                                               int max_order);

}  // namespace fogpipe::ar
