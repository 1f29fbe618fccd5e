// Stationarity of an AR model as stored: decided in extended precision, not from double-precision
// companion eigenvalues.
//
// Why: the slowest EMD components have a few cycles per record, so Burg's reflection coefficients
// come within ~1e-9 of 1 and the characteristic roots cluster near z = 1. A cluster of k roots
// moves by about eps^(1/k) under a relative perturbation eps of the coefficients (Wilkinson 1963,
// "Rounding Errors in Algebraic Processes", ch. 2), so rounding phi to double (eps = 1.1e-16) can
// push roots across the unit circle (an AR(8) cluster: 0.9999977 exact from the reflection
// coefficients, 1.00014 for the rounded phi), and the eigenvalues of the companion matrix, computed
// in double, cannot tell either way. The model that is run is the rounded phi, so that is the
// polynomial to judge.
//
// How: the Schur-Cohn test in its Levinson step-down form (reflection.h; Kay & Marple 1981, sec.
// V): z^p - phi_1 z^{p-1} - ... - phi_p has every root strictly inside |z| < rho exactly when every
// step-down coefficient of the scaled polynomial phi_i / rho^i is below 1 in magnitude. The stored
// doubles are exact in the wider type; the step-down divides by 1 - kappa_m^2, which loses as many
// digits as kappa_m is close to 1, so it runs in binary128 (113-bit significand, GCC/Clang's
// __float128 on x86-64; long double elsewhere): with kappa within 1e-10 of 1 it still carries ~20
// correct digits where double (and the 64-bit long double) would carry none or a few. A reflection
// coefficient within 1e-24 of +-1 counts as a root on the circle (beyond what the wide type can
// resolve; a time constant over 1e20 samples), and P(1) > 0, (-1)^p P(-1) > 0 are checked with
// exact sums: rounding does produce exact unit roots (Burg models of a trend whose rounded phi
// sums to exactly 1, found on the real ADIS16405 record). The largest root modulus is the smallest
// rho that passes, found by bisection.
#pragma once

#include <Eigen/Core>

namespace fogpipe::ar {

/// True when every root of z^p - phi_1 z^{p-1} - ... - phi_p lies strictly inside the unit circle,
/// for the coefficients exactly as stored (see the file comment). An empty phi is stationary.
bool IsStationaryAsStored(const Eigen::Ref<const Eigen::VectorXd>& phi);

/// The largest root modulus of that polynomial, to about 1e-15 relative near 1: consistent with
/// IsStationaryAsStored (below 1 exactly when it is true). 0 for an empty phi.
double MaxRootModulusAsStored(const Eigen::Ref<const Eigen::VectorXd>& phi);

/// The same for the coefficients c_i = phi_i - minus_i, the difference taken exactly (in the wide
/// type) from the stored doubles: a recursion that runs phi_i and minus_i as two products, like
/// the constant-gain Kalman loop (kalman/steady_state_filter.h), has this polynomial. False / NaN
/// when the sizes differ.
bool IsStationaryAsStored(const Eigen::Ref<const Eigen::VectorXd>& phi,
                          const Eigen::Ref<const Eigen::VectorXd>& minus);
double MaxRootModulusAsStored(const Eigen::Ref<const Eigen::VectorXd>& phi,
                              const Eigen::Ref<const Eigen::VectorXd>& minus);

}  // namespace fogpipe::ar
