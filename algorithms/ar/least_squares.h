// Conditional least squares by Householder QR (Golub & Van Loan, "Matrix Computations", 4th ed.,
// sec. 5.2 and 5.3), all orders 1..P from one factorisation.
//
// Rows t = P..N-1 of the lagged matrix Z = [x_{t-1}, ..., x_{t-P}, x_t] are reduced block by block
// to the (P+1) x (P+1) upper-triangular R with R'R = Z'Z: each block of rows is stacked under the
// current R and re-factorised with Eigen::HouseholderQR. This is the same R as one QR of all of Z
// (up to row signs) but needs O(block x P) memory instead of N x P, and Z'Z is never formed: the
// normal equations square the condition number (~1e12 on the slow IMFs), QR does not.
// Because lags come first in the column order, the order-p model uses the leading columns:
//   R[0:p, 0:p] phi_p = R[0:p, P],   RSS_p = sum_{i=p}^{P} R(i, P)^2,   sigma_p^2 = RSS_p / (N -
//   P),
// every order conditioned on the same first P samples, so the BIC compares like with like.
// Cost: 2 N (P+1)^2 flops.
#pragma once

#include <Eigen/Core>

#include "algorithms/ar/order_selection.h"

namespace fogpipe::ar {

/// Upper-triangular R, (order+1) x (order+1), with R'R = Z'Z for the lagged matrix above.
Eigen::MatrixXd LaggedTriangularFactor(const Eigen::Ref<const Eigen::VectorXd>& x_centered,
                                       int order);

/// Conditional least-squares models of orders 1..max_order. num_effective = N - max_order.
OrderSequence LeastSquaresAllOrders(const Eigen::Ref<const Eigen::VectorXd>& x_centered,
                                    int max_order);

}  // namespace fogpipe::ar
