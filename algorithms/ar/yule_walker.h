// Yule-Walker: biased autocovariance + Levinson-Durbin recursion (Durbin 1960; Box, Jenkins &
// Reinsel, sec. 3.2.2 and 7.3.1).
//
// The biased estimate r(k) = (1/N) sum_{t=0}^{N-1-k} x_t x_{t+k} is used because its Toeplitz
// matrix is positive semi-definite, so every |kappa_m| <= 1 and every model is stationary. Its
// known weakness: the 1/N taper biases the coefficients by O(1/N) times a factor that grows as the
// poles approach the unit circle (Kay & Marple 1981, sec. V.A), so on the slow IMFs Yule-Walker is
// visibly worse than Burg. It is offered for comparison with textbooks and statsmodels, not as the
// default. Innovation variance: r(0) prod (1 - kappa_m^2). num_effective = N.
#pragma once

#include <Eigen/Core>

#include "algorithms/ar/order_selection.h"

namespace fogpipe::ar {

/// Yule-Walker models of orders 1..max_order of `x_centered` (mean already removed).
OrderSequence YuleWalkerAllOrders(const Eigen::Ref<const Eigen::VectorXd>& x_centered,
                                  int max_order);

/// Levinson-Durbin on autocovariances r(0..P) (any common scale). Returns orders 1..P, stopping
/// early if the prediction error variance stops being positive. num_effective is left 0.
OrderSequence LevinsonDurbin(const Eigen::VectorXd& autocovariance);

}  // namespace fogpipe::ar
