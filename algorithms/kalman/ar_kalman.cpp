#include "algorithms/kalman/ar_kalman.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "algorithms/kalman/companion.h"
#include "algorithms/kalman/filter_phases.h"
#include "algorithms/kalman/noise_defaults.h"
#include "algorithms/kalman/rts_smoother.h"
#include "algorithms/kalman/steady_state_filter.h"

namespace fogpipe::kalman {
namespace {

ArKalmanResult Fail(ArKalmanResult result, Termination termination, std::string message) {
  result.filtered.resize(0);
  result.smoothed.resize(0);
  result.summary.termination = termination;
  result.summary.message = std::move(message);
  return result;
}
}  // namespace

const char* ToString(InitialCovariance initial_covariance) {
  switch (initial_covariance) {
    case InitialCovariance::kSampleVariance:
      return "sample_variance";
    case InitialCovariance::kSteadyState:
      return "steady_state";
  }
  return "unknown";
}

const char* ToString(GainSwitch gain_switch) {
  switch (gain_switch) {
    case GainSwitch::kNever:
      return "never";
    case GainSwitch::kFromStart:
      return "from_start";
    case GainSwitch::kConverged:
      return "converged";
    case GainSwitch::kStalled:
      return "stalled";
    case GainSwitch::kCapped:
      return "capped";
    case GainSwitch::kFrozen:
      return "frozen";
  }
  return "unknown";
}

bool ArKalmanOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (!std::isfinite(q) || !std::isfinite(r))
    return fail("ArKalmanOptions: q and r must be finite (negative selects the default)");
  if (!(q_scale >= 0.0) || !std::isfinite(q_scale))
    return fail("ArKalmanOptions::q_scale must be finite and >= 0");
  if (!(r_scale > 0.0) || !std::isfinite(r_scale))
    return fail("ArKalmanOptions::r_scale must be finite and > 0");
  if (!std::isfinite(mean)) return fail("ArKalmanOptions::mean must be finite");
  if (!std::isfinite(initial_variance))
    return fail("ArKalmanOptions::initial_variance must be finite (negative selects the default)");
  if (!(gain_tolerance >= 0.0) || !std::isfinite(gain_tolerance))
    return fail("ArKalmanOptions::gain_tolerance must be finite and >= 0");
  if (!(stall_tolerance >= 0.0) || !std::isfinite(stall_tolerance))
    return fail("ArKalmanOptions::stall_tolerance must be finite and >= 0");
  if (max_time_varying_steps < 0)
    return fail("ArKalmanOptions::max_time_varying_steps must be >= 0");
  if (initial_covariance != InitialCovariance::kSampleVariance &&
      initial_covariance != InitialCovariance::kSteadyState)
    return fail("ArKalmanOptions::initial_covariance is not a known start");
  return dare.IsValid(error);
}

namespace internal {

bool SampleVarianceIfFinite(const Eigen::Ref<const Eigen::VectorXd>& z, double* variance) {
  const Eigen::Index n = z.size();
  const double shift = z[0];
  double sum = 0.0, sum_sq = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double d = z[k] - shift;
    sum += d;
    sum_sq += d * d;
  }
  if (!std::isfinite(sum) || !std::isfinite(sum_sq)) return false;
  *variance = n < 2 ? 0.0 : std::max(0.0, (sum_sq - sum * sum / n) / static_cast<double>(n - 1));
  return true;
}

double GainDistance(const Eigen::VectorXd& g, const Eigen::VectorXd& g_inf) {
  const int p = static_cast<int>(g_inf.size());
  return GainDistance(g.data(), g_inf.data(), p, GainScale(g_inf.data(), p));
}

bool PrepareFilter(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
                   double innovation_variance, double white_noise_variance,
                   const ArKalmanOptions& options, bool check_z, ArKalmanResult* result_out,
                   DareSolution* dare_out, double* z_variance) {
  ArKalmanResult& result = *result_out;
  ArKalmanSummary& s = result.summary;
  const long long n = z.size();
  s.samples = n;
  auto fail = [&](Termination termination, std::string message) {
    result = Fail(std::move(result), termination, std::move(message));
    return false;
  };
  std::string error;
  if (!options.IsValid(&error)) return fail(Termination::kInvalidOptions, error);
  if (phi.size() == 0 || !phi.allFinite())
    return fail(Termination::kInvalidOptions, "phi must be non-empty, finite");
  if (n == 0) return fail(Termination::kInsufficientData, "empty series");
  if (check_z && !SampleVarianceIfFinite(z, z_variance))
    return fail(Termination::kNumericalFailure, "z has non-finite samples");

  // Noise levels: explicit or default, then the sweep scale factors (see ArKalmanOptions).
  const double r0 = options.r >= 0.0 ? options.r : white_noise_variance;
  if (!(r0 > 0.0) || !std::isfinite(r0))
    return fail(Termination::kInvalidOptions,
                "R must be > 0: set options.r or pass a positive white_noise_variance");
  double q0 = options.q;
  if (q0 < 0.0) {
    DefaultNoiseOptions dn_options;
    dn_options.dare = options.dare;
    const DefaultNoiseResult dn = DefaultNoise(phi, innovation_variance, r0, dn_options);
    if (!HasResult(dn.summary.termination))
      return fail(dn.summary.termination, "default q: " + dn.summary.message);
    q0 = dn.q;
  }
  result.q = q0 * options.q_scale;
  result.r = r0 * options.r_scale;

  DareSolution& dare = *dare_out;
  dare = SolveDare(phi, result.q, result.r, options.dare);
  s.riccati_iterations = dare.summary.iterations;
  s.riccati_relative_residual = dare.summary.relative_residual;
  if (!HasResult(dare.summary.termination))
    return fail(dare.summary.termination, "DARE: " + dare.summary.message);
  result.steady_state_gain = dare.gain;
  result.steady_state_error_variance = dare.filtered_covariance(0, 0);
  result.steady_state_innovation_variance = dare.innovation_variance;
  return true;
}

void SummarizeSteadyStart(const Eigen::VectorXd& phi, const DareSolution& dare, double q, double r,
                          ArKalmanSummary* s) {
  Eigen::MatrixXd pp, pf;
  Eigen::VectorXd g;
  PredictCovariance(dare.filtered_covariance, phi, q, &pp);
  JosephUpdate(pp, r, &g, &pf);
  s->initial_covariance = InitialCovariance::kSteadyState;
  s->gain_switch = GainSwitch::kFromStart;
  s->switched_at_sample = 0;
  s->gain_distance_at_switch = GainDistance(g, dare.gain);
}

// The diffuse start's largest variance, R / sqrt(eps), R the measurement-noise variance used.
// The time-varying recursion keeps P(k|k) to about eps P(0|0) absolute, and its first updates
// bring P(k|k) down to the order of R: with P(0|0) / R above 1 / eps the covariance, the gains and
// the smoother built on them are rounding noise (on the slowest IMFs var(z) / R reaches 1e20 and
// more; the smoother then left the signal by its own size). Below the bound the prior weighs at
// most sqrt(eps) ~ 1.5e-8 against one sample, so the start stays diffuse for the estimate, and the
// rounding stays at sqrt(eps) of R; the bound balances the two.
double InitialVarianceBound(double r) {
  return r / std::sqrt(std::numeric_limits<double>::epsilon());
}

PhaseStart DecidePhaseStart(const ArKalmanOptions& options, const DareSolution& dare, double q,
                            double r, double z_variance) {
  PhaseStart start;
  const bool dare_ok = dare.summary.termination == Termination::kSuccess;
  // The steady-state start needs a stabilizing DARE solution; without one, the paper's start.
  start.steady_start = options.initial_covariance == InitialCovariance::kSteadyState && dare_ok;
  if (options.initial_variance >= 0.0) {
    start.p0 = options.initial_variance;
  } else {
    const double bound = InitialVarianceBound(r);
    start.p0_bounded = r > 0.0 && z_variance > bound;
    start.p0 = start.p0_bounded ? bound : z_variance;
  }
  start.zero_covariance = !start.steady_start && q == 0.0 && start.p0 == 0.0;
  start.time_varying =
      !(start.steady_start && options.steady_state_switch) && !start.zero_covariance;
  start.may_switch = start.time_varying && options.steady_state_switch && dare_ok;
  return start;
}

bool ConstantGainLoopIsStable(const Eigen::VectorXd& phi, const PhaseEnd& end, std::string* why) {
  if ((end.constant_gain.array() == 0.0).all() && (end.x.array() == 0.0).all()) return true;
  double modulus = 0.0;
  if (ConstantGainLoopStable(phi, end.constant_gain, &modulus)) return true;
  char text[160];
  std::snprintf(text, sizeof(text),
                "constant-gain loop not stable in double precision (closed-loop root modulus "
                "%.9g): the model's roots are too close to z = 1 for this gain",
                modulus);
  *why = text;
  return false;
}
void FinishSummary(const ArKalmanOptions& options, const DareSolution& dare, bool zero_covariance,
                   ArKalmanSummary* summary) {
  ArKalmanSummary& s = *summary;
  const bool dare_ok = dare.summary.termination == Termination::kSuccess;
  s.termination = dare_ok || zero_covariance ? Termination::kSuccess : Termination::kNoConvergence;
  switch (s.gain_switch) {
    case GainSwitch::kNever:
      s.message = "time-varying filter to the end";
      break;
    case GainSwitch::kFromStart:
      s.message = "steady-state start: steady-state gain from the first sample";
      break;
    case GainSwitch::kConverged:
    case GainSwitch::kStalled:
      s.message =
          "switched to the steady-state gain (" + std::string(ToString(s.gain_switch)) + ")";
      break;
    case GainSwitch::kCapped:
      s.message = "switched to the steady-state gain at the time-varying step cap";
      break;
    case GainSwitch::kFrozen:
      s.message = "gain frozen at the time-varying step cap";
      break;
  }
  if (zero_covariance) {
    s.message = "q = 0 and P(0|0) = 0: gain 0 at every sample, the estimate is the mean";
  } else if (!dare_ok) {
    s.message = "DARE did not converge (" + dare.summary.message + ")" +
                (options.initial_covariance == InitialCovariance::kSteadyState
                     ? "; no steady-state start, started from the sample variance"
                     : "") +
                "; " + s.message;
  }
}
namespace {
// The smoother's output replaced by the filter's where the record contradicts the model in the
// smoother's direction (SmootherContradictsModel, rts_smoother.h).
void ReplaceContradictedSmoother(const Eigen::Ref<const Eigen::VectorXd>& z,
                                 ArKalmanResult* result) {
  double filtered_ms = 0.0, smoothed_ms = 0.0;
  if (!SmootherContradictsModel(z, result->filtered, result->smoothed, &filtered_ms, &smoothed_ms))
    return;
  result->smoothed = result->filtered;
  result->summary.smoother_replaced = true;
  char text[200];
  std::snprintf(text, sizeof(text),
                "smoothed residual mean square %.3g x the filtered one (the model predicts >= 1): "
                "the model takes noise for signal; the smoother's output is the filter's",
                smoothed_ms / filtered_ms);
  result->summary.smoother_note = text;
}
}  // namespace

void RunFilter(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
               const ArKalmanOptions& options, const DareSolution& dare, double z_variance,
               ArKalmanResult* result_out, Eigen::VectorXd* reuse) {
  ArKalmanResult& result = *result_out;
  const long long n = z.size();
  const Eigen::Index p = phi.size();
  if (reuse != nullptr && reuse->size() == n) result.filtered.swap(*reuse);
  result.filtered.resize(n);
  Eigen::VectorXd innovations;
  FilterGainHistory history;
  if (options.smooth) innovations.resize(n);
  const PhaseEnd end = RunTimeVaryingPhase(
      z, phi, options, dare, z_variance, &result,
      [&](long long k, double estimate, double e, const double* g, double innovation_var) {
        result.filtered[k] = estimate;
        if (options.smooth) {
          innovations[k] = e;
          history.time_varying_gains.insert(history.time_varying_gains.end(), g, g + p);
          history.time_varying_innovation_variances.push_back(innovation_var);
        }
      });
  const long long k = end.k;
  history.time_varying_steps = k;
  std::string unstable;
  if (k < n && !ConstantGainLoopIsStable(phi, end, &unstable)) {
    result = Fail(std::move(result), Termination::kNumericalFailure, unstable);
    result.summary.loop_unstable = true;
    return;
  }
  if (k < n) {
    SteadyStateFilter(z.data() + k, n - k, options.mean, phi, end.constant_gain, end.x,
                      result.filtered.data() + k,
                      options.smooth ? innovations.data() + k : nullptr);
  }

  if (options.smooth) {
    history.steady_state_gain = end.constant_gain;
    history.steady_state_innovation_variance = end.constant_innovation_variance;
    RtsSmoothInPlace(z, options.mean, phi, history, &innovations);
    result.smoothed = std::move(innovations);
    result.steady_state_smoothed_error_variance = SteadyStateSmoothedVariance(phi, dare);
    if (options.smoother_model_check) ReplaceContradictedSmoother(z, &result);
  }

  if (!result.filtered.allFinite()) {
    result = Fail(std::move(result), Termination::kNumericalFailure, "non-finite filter output");
    return;
  }
  FinishSummary(options, dare, end.zero_covariance, &result.summary);
}

}  // namespace internal

ArKalmanResult FilterAr(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
                        double innovation_variance, double white_noise_variance,
                        const ArKalmanOptions& options, Eigen::VectorXd* reuse) {
  ArKalmanResult result;
  DareSolution dare;
  double z_variance = 0.0;
  if (internal::PrepareFilter(z, phi, innovation_variance, white_noise_variance, options, true,
                              &result, &dare, &z_variance)) {
    internal::RunFilter(z, phi, options, dare, z_variance, &result, reuse);
  }
  return result;
}

}  // namespace fogpipe::kalman
