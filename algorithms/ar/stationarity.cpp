#include "algorithms/ar/stationarity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/ar/ar_model.h"

namespace fogpipe::ar {
namespace {

#if defined(__SIZEOF_FLOAT128__)
__extension__ typedef __float128 Wide;
// Reflection coefficients closer to +-1 than this count as on the circle: the step-down's rounding
// (~1e-34 relative, amplified by 1 / (1 - kappa^2) at each of the few steps with kappa near 1)
// cannot tell the side below ~1e-25, and a root that close to the circle has a time constant of
// more than 1e20 samples: a unit root for any record.
const Wide kOnTheCircle = Wide(1e-24);
#else
typedef long double Wide;
const Wide kOnTheCircle = Wide(1e-12);
#endif

Wide Abs(Wide v) { return v < 0 ? -v : v; }

// Every root of z^p - sum c_i z^{p-i}, c_i = phi_i - minus_i (minus may be null: 0), strictly
// inside |z| < rho: the step-down (reflection.cpp's map, in Wide) of a_i = c_i / rho^i has every
// |kappa_m| < 1. The difference is formed in Wide, so it is exact for the stored doubles.
bool RootsInside(const double* phi, const double* minus, Eigen::Index p, Wide rho) {
  if (p == 0) return true;
  if (!(rho > 0)) return false;
  std::vector<Wide> a(static_cast<std::size_t>(p)), prev(static_cast<std::size_t>(p));
  const Wide inverse = Wide(1) / rho;
  Wide power = 1;
  for (Eigen::Index i = 0; i < p; ++i) {
    if (!std::isfinite(phi[i]) || (minus != nullptr && !std::isfinite(minus[i]))) return false;
    power *= inverse;
    a[i] = (Wide(phi[i]) - (minus != nullptr ? Wide(minus[i]) : Wide(0))) * power;
  }
  // Necessary conditions, exact for rho = 1 whenever the stored coefficients span fewer than ~55
  // binary orders of magnitude (the sums are then exact in Wide): P(1) > 0 and (-1)^p P(-1) > 0
  // for P(z) = z^p - sum a_i z^{p-i}. They catch exact roots at z = +-1, which rounding produces:
  // Burg models of a trend whose rounded phi sums to exactly 1.
  Wide at_one = 1, at_minus_one = 1;
  for (Eigen::Index i = 0; i < p; ++i) {
    at_one -= a[i];
    at_minus_one -= (i % 2 == 0 ? -a[i] : a[i]);
  }
  if (!(at_one > 0) || !(at_minus_one > 0)) return false;
  for (Eigen::Index m = p; m >= 1; --m) {
    const Wide k = a[m - 1];
    if (!(Abs(k) < 1 - kOnTheCircle)) return false;
    const Wide denom = 1 - k * k;
    if (!(denom > 0)) return false;
    for (Eigen::Index j = 0; j + 1 < m; ++j) prev[j] = (a[j] + k * a[m - 2 - j]) / denom;
    std::swap(a, prev);
  }
  return true;
}

double MaxRootModulus(const double* phi, const double* minus, Eigen::Index p) {
  if (p == 0) return 0.0;
  Eigen::VectorXd c(p);  // the difference in double, for the first guess only
  for (Eigen::Index i = 0; i < p; ++i) c[i] = phi[i] - (minus != nullptr ? minus[i] : 0.0);
  if (!c.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const bool stationary = RootsInside(phi, minus, p, Wide(1));
  if ((c.array() == 0.0).all() && stationary) return 0.0;
  // A bracket [lo, hi] with roots inside |z| < hi and not all inside |z| < lo. The double-precision
  // eigenvalues give a first guess; Cauchy's bound 1 + max |c_i| (every root is inside it; widened
  // for the rounding of c) and 0 are the fallbacks.
  const double guess = CharacteristicRoots(c).cwiseAbs().maxCoeff();
  const double cauchy = 1.0 + c.cwiseAbs().maxCoeff();
  Wide hi = Wide(guess) * Wide(1.01) + Wide(1e-3);
  if (!(std::isfinite(guess) && RootsInside(phi, minus, p, hi))) hi = Wide(cauchy) * Wide(1.01);
  Wide lo = Wide(guess) * Wide(0.99) - Wide(1e-3);
  if (!(std::isfinite(guess) && lo > 0 && !RootsInside(phi, minus, p, lo))) lo = 0;
  // Far from the unit circle the verdict cannot change; the double eigenvalues are reported
  // unless they disagree with the bracket or the verdict.
  if (std::isfinite(guess) && std::abs(guess - 1.0) > 1e-2 && Wide(guess) > lo &&
      Wide(guess) < hi && (guess < 1.0) == stationary) {
    return guess;
  }
  for (int iteration = 0; iteration < 200 && hi - lo > hi * Wide(1e-17); ++iteration) {
    const Wide mid = (lo + hi) / 2;
    if (RootsInside(phi, minus, p, mid)) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  // The modulus is in [lo, hi). Rounded to double it can land on 1 for a root just inside; report
  // the double just below 1 then, so that the verdict and the modulus agree.
  double modulus = static_cast<double>(hi);
  if (stationary && !(modulus < 1.0)) modulus = std::nextafter(1.0, 0.0);
  if (!stationary && modulus < 1.0) modulus = 1.0;
  return modulus;
}

}  // namespace

bool IsStationaryAsStored(const Eigen::Ref<const Eigen::VectorXd>& phi) {
  return RootsInside(phi.data(), nullptr, phi.size(), Wide(1));
}

double MaxRootModulusAsStored(const Eigen::Ref<const Eigen::VectorXd>& phi) {
  return MaxRootModulus(phi.data(), nullptr, phi.size());
}

bool IsStationaryAsStored(const Eigen::Ref<const Eigen::VectorXd>& phi,
                          const Eigen::Ref<const Eigen::VectorXd>& minus) {
  return phi.size() == minus.size() && RootsInside(phi.data(), minus.data(), phi.size(), Wide(1));
}

double MaxRootModulusAsStored(const Eigen::Ref<const Eigen::VectorXd>& phi,
                              const Eigen::Ref<const Eigen::VectorXd>& minus) {
  if (phi.size() != minus.size()) return std::numeric_limits<double>::quiet_NaN();
  return MaxRootModulus(phi.data(), minus.data(), phi.size());
}

}  // namespace fogpipe::ar
