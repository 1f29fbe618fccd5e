// The steps of the paper's filter (FilterAr, ar_kalman.h), shared with the sweep's filter bank
// (ArFilterBank, ar_filter_bank.h), which runs the same steps in another order and must get the
// same bits (internal to algorithms/kalman).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "algorithms/common/fixed_order.h"
#include "algorithms/kalman/ar_kalman.h"
#include "algorithms/kalman/companion.h"
#include "algorithms/kalman/covariance_recursion.h"
#include "algorithms/kalman/riccati.h"
#include "algorithms/kernels/lanes.h"

namespace fogpipe::kalman::internal {

/// One pass over z: the sample variance (about z's own mean, shifted by z[0] against cancellation)
/// and whether every sample is finite (a non-finite sample makes the sums non-finite).
bool SampleVarianceIfFinite(const Eigen::Ref<const Eigen::VectorXd>& z, double* variance);

/// max_i |G_inf,i|, the scale of GainDistance.
inline double GainScale(const double* g_inf, int p) {
  double scale = 0.0;
  for (int i = 0; i < p; ++i) scale = std::max(scale, std::fabs(g_inf[i]));
  return scale;
}

/// max_i |G_i - G_inf,i| / scale (absolute if scale = 0); NaN if any element of G is NaN.
inline double GainDistance(const double* g, const double* g_inf, int p, double scale) {
  double diff = 0.0;
  for (int i = 0; i < p; ++i) {
    const double d = std::fabs(g[i] - g_inf[i]);
    if (std::isnan(d)) return d;
    if (d > diff) diff = d;
  }
  return scale > 0.0 ? diff / scale : diff;
}

/// max_i |G_i - G_inf,i| / max_i |G_inf,i| (absolute if G_inf = 0).
double GainDistance(const Eigen::VectorXd& g, const Eigen::VectorXd& g_inf);

/// Validation, noise levels and the DARE: everything before the first sample. False (with the
/// result failed) if there is nothing to filter. check_z: make the pass over z (sample variance and
/// finiteness); without it *z_variance is left as it is (callers that made that pass themselves).
bool PrepareFilter(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
                   double innovation_variance, double white_noise_variance,
                   const ArKalmanOptions& options, bool check_z, ArKalmanResult* result_out,
                   DareSolution* dare_out, double* z_variance);

/// The summary of a steady-state start; gain_distance_at_switch from one Riccati step from P0.
void SummarizeSteadyStart(const Eigen::VectorXd& phi, const DareSolution& dare, double q, double r,
                          ArKalmanSummary* s);

// Where the time-varying phase leaves the filter: the constant-gain loop starts at sample `k`
// (n if it never does) from X(k-1|k-1) = x, with `constant_gain` (G_inf, a frozen gain or 0).
struct PhaseEnd {
  long long k = 0;
  Eigen::VectorXd x;
  Eigen::VectorXd constant_gain;
  double constant_innovation_variance = 0.0;
  bool zero_covariance = false;
};

// The time-varying phase proper (RunTimeVaryingPhase): from X(0|0) = end->x and the recursion at
// P(0|0), steps until the gain has converged, stalled or reached the cap (filling the summary's
// switch fields and, for a frozen gain, end's constant gain), or to the end of z. may_switch: a
// switch to G_inf is allowed (PhaseStart). Returns the first sample not filtered.
template <typename Recursion, typename Emit>
long long TimeVaryingLoop(Recursion&& recursion, const Eigen::Ref<const Eigen::VectorXd>& z,
                          const Eigen::VectorXd& phi, const ArKalmanOptions& options,
                          const DareSolution& dare, bool may_switch, ArKalmanSummary* summary,
                          PhaseEnd* end, Emit&& emit) {
  ArKalmanSummary& s = *summary;
  const long long n = z.size();
  constexpr int P = std::decay_t<Recursion>::kOrder;
  const int p = P > 0 ? P : static_cast<int>(phi.size());
  // The state X(k|k) and phi in plain arrays (order P at compile time where it is known); every
  // multiply-add spelled out, so FilterAr and ArFilterBank, which instantiate this loop with
  // different emitters, compute the same bits (algorithms/kernels/lanes.h).
  fixed_order::Buffer<P> x_buffer(p), phi_buffer(p), g_inf_buffer(p);
  double* x = x_buffer.get();
  double* phi_a = phi_buffer.get();
  double* g_inf = g_inf_buffer.get();
  for (int i = 0; i < p; ++i) {
    x[i] = end->x[i];
    phi_a[i] = phi[i];
    g_inf[i] = dare.gain.size() == p ? dare.gain[i] : 0.0;
  }
  const double g_inf_scale = GainScale(g_inf, p);
  long long cap = options.steady_state_switch && options.max_time_varying_steps > 0
                      ? options.max_time_varying_steps
                      : std::numeric_limits<long long>::max();
  double best_distance = std::numeric_limits<double>::infinity();
  long long best_at = 0;
  Eigen::VectorXd gain_at_half_cap;
  long long k = 0;
  for (; k < n; ++k) {
    const double innovation_var = recursion.Step();
    if (may_switch) {
      const double distance = GainDistance(recursion.gain(), g_inf, p, g_inf_scale);
      if (distance < best_distance) {
        best_distance = distance;
        best_at = k;
      }
      // Converged, or stalled at the rounding floor of the recursion: no new minimum for as
      // many steps as it took to reach the current one (a converging recursion keeps shrinking
      // the distance geometrically), while the gain is within stall_tolerance now. (Not only
      // its best: at its floor the gain wanders, and imf6 of Table 2 at q/R = 1e-10 had drifted
      // from 1e-9 back to 1.5e-8 when its minimum was 4000 steps old, so a switch there moved
      // the output by 3.5e-9 relative.)
      const bool stalled = best_distance <= options.stall_tolerance &&
                           distance <= options.stall_tolerance && k - best_at > best_at &&
                           k - best_at >= 64;
      if (distance <= options.gain_tolerance || stalled || k >= cap) {
        s.gain_switch = distance <= options.gain_tolerance ? GainSwitch::kConverged
                        : stalled                          ? GainSwitch::kStalled
                                                           : GainSwitch::kCapped;
        s.switched_at_sample = k;
        s.gain_distance_at_switch = distance;
        break;
      }
    } else if (k == cap / 2) {
      gain_at_half_cap = Eigen::Map<const Eigen::VectorXd>(recursion.gain(), p);
    } else if (k >= cap) {
      // (The gain of this step: a replayed recursion's pointer changes with every step.)
      const Eigen::Map<const Eigen::VectorXd> g(recursion.gain(), p);
      // No steady-state gain to switch to: keep this gain if it stabilizes the loop (the
      // time-varying gain of a decreasing Riccati iterate does; Bitmead, Gevers & Wertz 1985,
      // the "fake algebraic Riccati equation"), else stay time-varying to the end.
      if (IsStableLoop(phi, g)) {
        end->constant_gain = g;
        end->constant_innovation_variance = innovation_var;
        s.gain_switch = GainSwitch::kFrozen;
        s.switched_at_sample = k;
        s.gain_distance_at_switch = GainDistance(gain_at_half_cap, g);
        break;
      }
      cap = std::numeric_limits<long long>::max();
    }
    const double* gk = recursion.gain();
    double pred = 0.0;
    for (int i = 0; i < p; ++i) pred = kernels::MulAdd(phi_a[i], x[i], pred);
    const double e = (z[k] - options.mean) - pred;
    for (int i = p - 1; i >= 1; --i) x[i] = kernels::MulAdd(gk[i], e, x[i - 1]);
    x[0] = kernels::MulAdd(gk[0], e, pred);
    emit(k, x[0] + options.mean, e, gk, innovation_var);
  }
  for (int i = 0; i < p; ++i) end->x[i] = x[i];
  return k;
}

// How RunTimeVaryingPhase starts a filter, decided in one place (MakeGainTapes must know which
// filters take the time-varying loop from which P(0|0)).
struct PhaseStart {
  /// P(0|0) is the DARE solution: asked for, and the DARE has a stabilizing solution.
  bool steady_start = false;
  /// Else P(0|0) = p0 I (eq. 7): the given initial variance, or the sample variance of z bounded
  /// by InitialVarianceBound (ar_kalman.cpp).
  double p0 = 0.0;
  /// The sample variance of z exceeded the bound and p0 is the bound.
  bool p0_bounded = false;
  /// q = 0 from P(0|0) = 0: P(k|k-1) = A 0 A' + 0 = 0 at every step, so the gain is exactly 0
  /// from the first sample and the estimate is the mean, whatever the DARE says (it is ill-posed
  /// at q = 0 on the near-unit-root models of slow IMFs and would leave the loop time-varying).
  bool zero_covariance = false;
  /// TimeVaryingLoop runs (not the steady start with its switch, not zero covariance) ...
  bool time_varying = false;
  /// ... and may switch to G_inf (TimeVaryingLoop's may_switch).
  bool may_switch = false;
};

/// r: the measurement-noise variance the filter uses (ArKalmanResult::r).
PhaseStart DecidePhaseStart(const ArKalmanOptions& options, const DareSolution& dare, double q,
                            double r, double z_variance);

/// RunTimeVaryingPhase's default: no replayed gains, the phase runs its own covariance recursion.
struct OwnRecursion {
  template <typename Order, typename Run>
  bool operator()(Order, Run&&) const {
    return false;
  }
};

// The filter from X(0|0) = 0 up to its constant-gain loop, after PrepareFilter: the start P(0|0),
// then the time-varying recursion (eqs. 8-11, Joseph form) until the gain has converged, stalled
// or reached the cap. emit(k, estimate, e, gain, innovation_variance) receives every sample of
// the time-varying phase. Fills the summary's start and switch fields. replay(order, run) may run
// the loop on gains computed elsewhere (the sweep's gain tapes, ar_filter_bank.cpp) by calling
// run(recursion) and returning true; else the phase runs its own CovarianceRecursion.
template <typename Emit, typename Replay = OwnRecursion>
PhaseEnd RunTimeVaryingPhase(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
                             const ArKalmanOptions& options, const DareSolution& dare,
                             double z_variance, ArKalmanResult* result_out, Emit&& emit,
                             Replay replay = {}) {
  ArKalmanResult& result = *result_out;
  ArKalmanSummary& s = result.summary;
  const Eigen::Index p = phi.size();
  PhaseEnd end;
  end.x = Eigen::VectorXd::Zero(p);  // X(0|0) = 0 (eq. 7)
  Eigen::MatrixXd pf(p, p);          // P(0|0)
  const PhaseStart start = DecidePhaseStart(options, dare, result.q, result.r, z_variance);
  s.initial_covariance =
      start.steady_start ? InitialCovariance::kSteadyState : InitialCovariance::kSampleVariance;
  s.initial_variance_bounded = !start.steady_start && start.p0_bounded;
  if (start.steady_start) {
    pf = dare.filtered_covariance;
  } else {
    pf = start.p0 * Eigen::MatrixXd::Identity(p, p);  // P(0|0) = var(x0) I (eq. 7)
  }
  end.zero_covariance = start.zero_covariance;

  // The constant gain of the O(p) loop and its innovation variance: G_inf, or a frozen gain.
  end.constant_gain = dare.gain;
  end.constant_innovation_variance = dare.innovation_variance;
  long long k = 0;
  if (start.time_varying) {
    // Time-varying filter (eqs. 8-11), Joseph form, until the gain has converged, stalled or
    // reached the cap; the covariance recursion with the order at compile time where it can.
    fixed_order::WithWideFixedOrder(static_cast<int>(p), [&](auto order) {
      constexpr int kP = decltype(order)::value;
      const auto run = [&](auto&& recursion) {
        k = TimeVaryingLoop(recursion, z, phi, options, dare, start.may_switch, &s, &end, emit);
      };
      if (!replay(order, run)) run(CovarianceRecursion<kP>(pf, phi, result.q, result.r));
    });
  } else if (end.zero_covariance) {
    end.constant_gain = Eigen::VectorXd::Zero(p);
    end.constant_innovation_variance = result.r;
    s.gain_switch = GainSwitch::kFromStart;
    s.switched_at_sample = 0;
    s.gain_distance_at_switch = 0.0;
  } else {
    // The steady-state start with its switch: P0 is the fixed point, G(k) = G_inf for every k.
    SummarizeSteadyStart(phi, dare, result.q, result.r, &s);
  }
  end.k = k;
  return end;
}

/// The constant-gain loop about to run from `end` is stable as it runs (ConstantGainLoopStable);
/// else fills *why (FilterAr and ArFilterBank alike report it as a numerical failure, without
/// output). A zero gain from a zero state (the zero-covariance start of a pure-noise component)
/// needs no check: the loop's input enters through beta = 0 and its state stays exactly 0, so the
/// output is the mean whatever the model's roots.
bool ConstantGainLoopIsStable(const Eigen::VectorXd& phi, const PhaseEnd& end, std::string* why);

/// Termination and message of a filter that ran (FilterAr and ArFilterBank alike).
void FinishSummary(const ArKalmanOptions& options, const DareSolution& dare, bool zero_covariance,
                   ArKalmanSummary* summary);

/// The whole filter (and smoother), after PrepareFilter.
void RunFilter(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
               const ArKalmanOptions& options, const DareSolution& dare, double z_variance,
               ArKalmanResult* result_out, Eigen::VectorXd* reuse);

}  // namespace fogpipe::kalman::internal
