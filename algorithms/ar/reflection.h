// Reflection coefficients (partial autocorrelations) and the Levinson step-up / step-down maps.
//
// Convention used everywhere in fogpipe::ar: the recursion coefficients phi of
//   x_k = phi_1 x_{k-1} + ... + phi_p x_{k-p} + e_k
// and the reflection coefficient kappa_m = phi_{m,m}, the last coefficient of the order-m model
// (the partial autocorrelation at lag m). The order update is Durbin's (Durbin 1960;
// Box, Jenkins & Reinsel, "Time Series Analysis", 4th ed., eq. 3.2.37):
//   phi_{m,j} = phi_{m-1,j} - kappa_m phi_{m-1,m-j},  j = 1..m-1;   phi_{m,m} = kappa_m.
// A model is stationary exactly when every |kappa_m| < 1 (Schur-Cohn; Kay & Marple 1981, sec. V).
#pragma once

#include <Eigen/Core>

namespace fogpipe::ar {

/// Step-up: reflection coefficients kappa_1..kappa_p -> recursion coefficients phi_1..phi_p.
Eigen::VectorXd StepUp(const Eigen::Ref<const Eigen::VectorXd>& kappa);

/// One Durbin order update in place: phi (order m-1) -> order m with reflection coefficient kappa.
void StepUpOnce(double kappa, Eigen::VectorXd* phi);

/// Step-down (inverse Levinson): phi -> kappa. Returns false (and leaves kappa partially filled)
/// when some |kappa_m| >= 1, i.e. the model is not stationary and the map is not defined.
bool StepDown(const Eigen::Ref<const Eigen::VectorXd>& phi, Eigen::VectorXd* kappa);

}  // namespace fogpipe::ar
