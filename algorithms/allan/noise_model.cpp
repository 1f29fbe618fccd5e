#include "algorithms/allan/noise_model.h"

#include <cmath>
#include <limits>

#include "algorithms/common/units.h"

namespace fogpipe::allan {

double TermAllanVariance(Term term, const TermParams& p, double tau_s) {
  const double a2 = p.amplitude * p.amplitude;
  const double tau = tau_s;
  if (!(tau > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  switch (term) {
    case Term::kQuantization:
      return 3.0 * a2 / (tau * tau);
    case Term::kAngleRandomWalk:
      return a2 / tau;
    case Term::kBiasInstability:
      return 2.0 * std::log(2.0) / units::kPi * a2;
    case Term::kRateRandomWalk:
      return a2 * tau / 3.0;
    case Term::kRateRamp:
      return a2 * tau * tau / 2.0;
    case Term::kSinusoid: {
      const double x = units::kPi * p.frequency_hz * tau;
      if (x == 0.0) return 0.0;
      const double s = std::sin(x);
      const double g = s * s / x;
      return a2 * g * g;
    }
    case Term::kGaussMarkov: {
      const double tc = p.correlation_time_s;
      if (!(tc > 0.0)) return std::numeric_limits<double>::quiet_NaN();
      const double q = 2.0 * a2 / tc;
      const double u = tau / tc;
      // For u << 1 the bracket cancels catastrophically (it is O(u^2)); use its Taylor series
      // 1 - (3 - 4e^-u + e^-2u) / (2u) = u^2/3 - u^3/4 + 7u^4/60 - u^5/24 + O(u^6), whose
      // truncation error at u < 1e-2 is below 1e-9 relative.
      double bracket;
      if (u < 1e-2) {
        bracket = u * u * (1.0 / 3.0 + u * (-1.0 / 4.0 + u * (7.0 / 60.0 - u / 24.0)));
      } else {
        bracket = 1.0 - (3.0 - 4.0 * std::exp(-u) + std::exp(-2.0 * u)) / (2.0 * u);
      }
      return q * tc * tc / tau * bracket;
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double TermSlope(Term term) {
  switch (term) {
    case Term::kQuantization:
      return -1.0;
    case Term::kAngleRandomWalk:
      return -0.5;
    case Term::kBiasInstability:
      return 0.0;
    case Term::kRateRandomWalk:
      return 0.5;
    case Term::kRateRamp:
      return 1.0;
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace fogpipe::allan
