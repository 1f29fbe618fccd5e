#include "algorithms/kalman/noise_defaults.h"

#include <cmath>

namespace fogpipe::kalman {

bool DefaultNoiseOptions::IsValid(std::string* error) const {
  if (!(relative_tolerance > 0.0) || !std::isfinite(relative_tolerance)) {
    if (error) *error = "DefaultNoiseOptions::relative_tolerance must be finite and > 0";
    return false;
  }
  if (max_iterations < 1) {
    if (error) *error = "DefaultNoiseOptions::max_iterations must be >= 1";
    return false;
  }
  return dare.IsValid(error);
}

double WhiteNoiseVarianceFromArw(double arw_rad_per_sqrt_s, double sample_rate_hz) {
  return arw_rad_per_sqrt_s * arw_rad_per_sqrt_s * sample_rate_hz;
}

DefaultNoiseResult DefaultNoise(const Eigen::VectorXd& phi, double innovation_variance,
                                double white_noise_variance, const DefaultNoiseOptions& options) {
  DefaultNoiseResult out;
  DefaultNoiseSummary& s = out.summary;
  std::string error;
  if (!options.IsValid(&error)) {
    s.message = error;
    return out;
  }
  if (phi.size() == 0 || !phi.allFinite()) {
    s.message = "phi must be non-empty and finite";
    return out;
  }
  if (!(innovation_variance > 0.0) || !std::isfinite(innovation_variance) ||
      !(white_noise_variance > 0.0) || !std::isfinite(white_noise_variance)) {
    s.message = "need finite innovation_variance > 0 and white_noise_variance > 0";
    return out;
  }
  const double target = innovation_variance;
  const double r = white_noise_variance;
  out.r = r;

  // f(q) = S(q) - target, increasing; f(0) = R - target for a stable AR polynomial.
  bool failed = false;
  auto f = [&](double q) {
    const DareSolution d = SolveDare(phi, q, r, options.dare);
    if (!HasResult(d.summary.termination)) failed = true;
    return d.innovation_variance - target;
  };
  double lo = 0.0;
  double f_lo = f(lo);
  if (failed) {
    s.termination = Termination::kNumericalFailure;
    s.message = "DARE failed at q = 0";
    return out;
  }
  if (f_lo >= 0.0) {
    s.termination = Termination::kSuccess;
    s.q_clamped_to_zero = true;
    s.message = "AR innovation variance <= white-noise variance: no process noise left, q = 0";
    out.q = 0.0;
    out.implied_innovation_variance = f_lo + target;
    return out;
  }
  double hi = target - r;  // S(q) >= q + R, so f(hi) >= 0
  double f_hi = f(hi);
  int side = 0;
  double q = hi;
  double fq = f_hi;
  bool converged = false;
  for (int it = 1; it <= options.max_iterations && !failed; ++it) {
    s.iterations = it;
    q = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    fq = f(q);
    if (std::abs(fq) <= options.relative_tolerance * target ||
        hi - lo <= options.relative_tolerance * q) {
      converged = true;
      break;
    }
    if (fq < 0.0) {
      lo = q;
      f_lo = fq;
      if (side == -1) f_hi *= 0.5;  // Illinois: halve the stale end
      side = -1;
    } else {
      hi = q;
      f_hi = fq;
      if (side == 1) f_lo *= 0.5;
      side = 1;
    }
  }
  if (failed) {
    s.termination = Termination::kNumericalFailure;
    s.message = "DARE failed during the root search";
    return out;
  }
  out.q = q;
  out.implied_innovation_variance = fq + target;
  s.termination = converged ? Termination::kSuccess : Termination::kNoConvergence;
  s.message = converged ? "q matched to the AR innovation variance" : "root search hit its cap";
  return out;
}

}  // namespace fogpipe::kalman
