// Chi-square tail probabilities through the regularized incomplete gamma function.
//
// Q(a, x) = Gamma(a, x) / Gamma(a), by its power series for x < a + 1 (Q = 1 - P) and by Lentz's
// continued fraction otherwise (Numerical Recipes, 3rd ed., sec. 6.2, gser/gcf; Abramowitz &
// Stegun 6.5.29 and 6.5.31). Relative accuracy ~1e-14 over the range the Ljung-Box test needs.
#pragma once

namespace fogpipe::ar {

/// Regularized upper incomplete gamma Q(a, x), a > 0, x >= 0. NaN for invalid arguments.
double RegularizedGammaQ(double a, double x);

/// P(X > x) for X ~ chi-square with `dof` degrees of freedom: Q(dof / 2, x / 2).
double ChiSquareSurvival(double x, double dof);

}  // namespace fogpipe::ar
