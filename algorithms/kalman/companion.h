// Covariance algebra of the AR(p) companion state-space model (the paper's eqs. 5-10,
// docs/method.md), in O(p^2).
//
// State X(k) = [x(k), x(k-1), ..., x(k-p+1)]', transition A = companion(phi) (first row phi',
// ones on the subdiagonal), process noise Q = diag(q, 0, ..., 0), measurement H = [1 0 ... 0].
// A dense A P A' costs O(p^3); with a companion A it is a shift of P by one row and column plus one
// new row, phi' P and phi' P phi, so one filter step stays O(p^2).
#pragma once

#include <Eigen/Core>

namespace fogpipe::kalman {

/// The p x p companion matrix of x(k) = sum_i phi_i x(k-i) + w(k).
Eigen::MatrixXd CompanionMatrix(const Eigen::VectorXd& phi);

/// P(k|k-1) = A P(k-1|k-1) A' + Q (eq. 8) for the companion A, in O(p^2).
/// `predicted` must not alias `filtered`; it is resized if needed.
void PredictCovariance(const Eigen::MatrixXd& filtered, const Eigen::VectorXd& phi, double q,
                       Eigen::MatrixXd* predicted);

/// The measurement update with H = [1 0 ... 0] and scalar R:
/// S = P00 + R, G = P(:,0) / S (eq. 9) and, in Joseph form,
/// P(k|k) = (I - G H) P (I - G H)' + G R G' (eq. 10, the form that stays symmetric and positive
/// semi-definite under rounding; Bucy & Joseph 1968). With H = e1 this is
/// P - G c' - c G' + (P00 + R) G G', c = P(:,0), again O(p^2).
/// Returns S, the innovation variance; `gain` and `filtered` are resized if needed.
double JosephUpdate(const Eigen::MatrixXd& predicted, double r, Eigen::VectorXd* gain,
                    Eigen::MatrixXd* filtered);

}  // namespace fogpipe::kalman
