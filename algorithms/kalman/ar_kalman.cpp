#include "algorithms/kalman/ar_kalman.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "algorithms/common/fixed_order.h"
#include "algorithms/kalman/companion.h"
#include "algorithms/kalman/covariance_recursion.h"
#include "algorithms/kalman/mul_add.h"
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

// One pass over z: the sample variance (about z's own mean, shifted by z[0] against cancellation)
// and whether every sample is finite (a non-finite sample makes the sums non-finite).
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

// max_i |G_i - G_inf,i| / max_i |G_inf,i| (absolute if G_inf = 0).
// max_i |G_inf,i|, the scale of GainDistance.
double GainScale(const double* g_inf, int p) {
  double scale = 0.0;
  for (int i = 0; i < p; ++i) scale = std::max(scale, std::fabs(g_inf[i]));
  return scale;
}

// max_i |G_i - G_inf,i| / scale (absolute if scale = 0); NaN if any element of G is NaN.
double GainDistance(const double* g, const double* g_inf, int p, double scale) {
  double diff = 0.0;
  for (int i = 0; i < p; ++i) {
    const double d = std::fabs(g[i] - g_inf[i]);
    if (std::isnan(d)) return d;
    if (d > diff) diff = d;
  }
  return scale > 0.0 ? diff / scale : diff;
}

// max_i |G_i - G_inf,i| / max_i |G_inf,i| (absolute if G_inf = 0).
double GainDistance(const Eigen::VectorXd& g, const Eigen::VectorXd& g_inf) {
  const int p = static_cast<int>(g_inf.size());
  return GainDistance(g.data(), g_inf.data(), p, GainScale(g_inf.data(), p));
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

namespace {

// Validation, noise levels and the DARE: everything before the first sample. False (with the
// result failed) if there is nothing to filter. check_z: make the pass over z (sample variance and
// finiteness); without it *z_variance is left as it is (callers that made that pass themselves).
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

// The summary of a steady-state start; gain_distance_at_switch from one Riccati step from P0.
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
  // different emitters, compute the same bits (mul_add.h).
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
    for (int i = 0; i < p; ++i) pred = internal::MulAdd(phi_a[i], x[i], pred);
    const double e = (z[k] - options.mean) - pred;
    for (int i = p - 1; i >= 1; --i) x[i] = internal::MulAdd(gk[i], e, x[i - 1]);
    x[0] = internal::MulAdd(gk[0], e, pred);
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
  /// by InitialVarianceBound.
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

// The gain sequences G(k) and innovation variances S(k) of up to four time-varying filters of one
// AR model, computed side by side (internal::CovarianceLanes) on demand, a chunk of steps at a
// time, and kept for TimeVaryingLoop to replay one filter after the other (ReplayedRecursion).
// The recursion does not depend on the data, so the replayed filters are those of
// CovarianceRecursion to the last bit (tested through ArFilterBank against FilterAr).
class GainTape {
 public:
  virtual ~GainTape() = default;
  /// Computes the steps up to at least `steps` (at most the limit given at construction).
  virtual void ExtendTo(long long steps) = 0;
  long long steps() const { return steps_; }
  double innovation_variance(int lane, long long k) const {
    return variances_[lane][static_cast<std::size_t>(k)];
  }
  const double* gain(int lane, long long k) const {
    return gains_[lane].data() + static_cast<std::size_t>(k) * p_;
  }

 protected:
  explicit GainTape(int p) : p_(p) {}
  int p_;
  long long steps_ = 0;
  std::vector<double> variances_[4], gains_[4];
};

template <int P>
class LaneGainTape final : public GainTape {
 public:
  // Steps are computed in chunks, so a group whose filters all switch early costs at most one
  // chunk more than its longest filter. (Measured on the sweep benchmark's 1 h at 100 Hz: of 1760
  // filters a quarter switch within 80 samples, more than half only at the 4096-step cap.)
  static constexpr long long kChunk = 256;
  LaneGainTape(const Eigen::MatrixXd* const filtered0[4], const Eigen::VectorXd& phi,
               const double q[4], const double r[4], int active, long long limit)
      : GainTape(P), lanes_(filtered0, phi, q, r, active), active_(active), limit_(limit) {
    // Room for the longest phase at once (untouched memory costs nothing; regrowing copies).
    for (int m = 0; m < active; ++m) {
      variances_[m].reserve(static_cast<std::size_t>(limit));
      gains_[m].reserve(static_cast<std::size_t>(limit) * P);
    }
  }
  void ExtendTo(long long steps) override {
    const long long target = std::min(limit_, (steps + kChunk - 1) / kChunk * kChunk);
    for (; steps_ < target; ++steps_) {
      const internal::CovarianceLanes4 s = lanes_.Step();
      const internal::CovarianceLanes4* g = lanes_.gain();
      for (int m = 0; m < active_; ++m) {
        variances_[m].push_back(s[m]);
        for (int i = 0; i < P; ++i) gains_[m].push_back(g[i][m]);
      }
    }
  }

 private:
  internal::CovarianceLanes<P> lanes_;
  int active_;
  long long limit_;
};

// The Recursion interface of TimeVaryingLoop over one lane of a GainTape.
template <int P>
class ReplayedRecursion {
 public:
  static constexpr int kOrder = P;
  ReplayedRecursion(GainTape* tape, int lane) : tape_(tape), lane_(lane) {}
  double Step() {
    ++k_;
    if (k_ >= tape_->steps()) tape_->ExtendTo(k_ + 1);
    // MakeGainTapes sizes the tape for every step TimeVaryingLoop can take.
    if (k_ >= tape_->steps()) throw std::logic_error("gain tape shorter than the phase");
    return tape_->innovation_variance(lane_, k_);
  }
  const double* gain() const { return tape_->gain(lane_, k_); }

 private:
  GainTape* tape_;
  int lane_;
  long long k_ = -1;
};

// A filter's replayed lane, if it has one.
struct TapeLane {
  GainTape* tape = nullptr;
  int lane = 0;
};

// The filter from X(0|0) = 0 up to its constant-gain loop, after PrepareFilter: the start P(0|0),
// then the time-varying recursion (eqs. 8-11, Joseph form) until the gain has converged, stalled
// or reached the cap. emit(k, estimate, e, gain, innovation_variance) receives every sample of
// the time-varying phase. Fills the summary's start and switch fields.
template <typename Emit>
PhaseEnd RunTimeVaryingPhase(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
                             const ArKalmanOptions& options, const DareSolution& dare,
                             double z_variance, ArKalmanResult* result_out, Emit&& emit,
                             TapeLane tape = {}) {
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
      if constexpr (kP > 0) {
        if (tape.tape != nullptr) {
          k = TimeVaryingLoop(ReplayedRecursion<kP>(tape.tape, tape.lane), z, phi, options, dare,
                              start.may_switch, &s, &end, emit);
          return;
        }
      }
      k = TimeVaryingLoop(internal::CovarianceRecursion<kP>(pf, phi, result.q, result.r), z, phi,
                          options, dare, start.may_switch, &s, &end, emit);
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

// The constant-gain loop about to run from `end` is stable as it runs (ConstantGainLoopStable);
// else fills *why (FilterAr and ArFilterBank alike report it as a numerical failure, without
// output). A zero gain from a zero state (the zero-covariance start of a pure-noise component)
// needs no check: the loop's input enters through beta = 0 and its state stays exactly 0, so the
// output is the mean whatever the model's roots.
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

// Termination and message of a filter that ran (FilterAr and ArFilterBank alike).
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

// The whole filter (and smoother), after PrepareFilter.
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
  }

  if (!result.filtered.allFinite()) {
    result = Fail(std::move(result), Termination::kNumericalFailure, "non-finite filter output");
    return;
  }
  FinishSummary(options, dare, end.zero_covariance, &result.summary);
}

}  // namespace

ArKalmanResult FilterAr(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
                        double innovation_variance, double white_noise_variance,
                        const ArKalmanOptions& options, Eigen::VectorXd* reuse) {
  ArKalmanResult result;
  DareSolution dare;
  double z_variance = 0.0;
  if (PrepareFilter(z, phi, innovation_variance, white_noise_variance, options, true, &result,
                    &dare, &z_variance)) {
    RunFilter(z, phi, options, dare, z_variance, &result, reuse);
  }
  return result;
}

namespace {

// A tape keeps (p + 1) doubles per step and lane: at most 6.8 MB per lane at order 12.
constexpr long long kMaxTapeSteps = 1LL << 16;

// The filters of a bank whose time-varying phase RunTimeVaryingPhase runs from the paper's start
// with a switch to come (its TimeVaryingLoop branch with may_switch), with a bounded cap and a
// fixed order: four at a time, their gain sequences computed side by side (GainTape); a single
// filter left over keeps the scalar recursion (one lane would cost as much). Returns each
// filter's lane (none for the others) and keeps the tapes in *owner.
std::vector<TapeLane> MakeGainTapes(const Eigen::VectorXd& phi,
                                    const std::vector<ArKalmanOptions>& options,
                                    const std::vector<ArKalmanResult>& results,
                                    const std::vector<DareSolution>& dares,
                                    const std::vector<bool>& prepared, double z_variance,
                                    long long n, std::vector<std::unique_ptr<GainTape>>* owner) {
  std::vector<TapeLane> tapes(options.size());
  const int p = static_cast<int>(phi.size());
  if (p < 1 || p > fixed_order::kMaxWideFixedOrder || n < 1) return tapes;
  std::vector<std::size_t> eligible;
  std::vector<double> p0(options.size(), 0.0);
  for (std::size_t i = 0; i < options.size(); ++i) {
    if (!prepared[i] || options[i].smooth) continue;
    // A switch to come (may_switch) bounds the phase by the cap (a time-varying start without
    // one could run to the end of z), and may_switch implies the paper's start, p0 I.
    const PhaseStart start =
        DecidePhaseStart(options[i], dares[i], results[i].q, results[i].r, z_variance);
    const long long cap = options[i].max_time_varying_steps;
    if (start.may_switch && cap > 0 && cap <= kMaxTapeSteps) {
      eligible.push_back(i);
      p0[i] = start.p0;
    }
  }
  for (std::size_t first = 0; first + 1 < eligible.size(); first += 4) {
    const int active = static_cast<int>(std::min<std::size_t>(4, eligible.size() - first));
    std::vector<Eigen::MatrixXd> start(active);
    const Eigen::MatrixXd* starts[4] = {};
    double q[4] = {}, r[4] = {};
    long long limit = 0;
    for (int m = 0; m < active; ++m) {
      const std::size_t i = eligible[first + m];
      start[m] = p0[i] * Eigen::MatrixXd::Identity(p, p);  // P(0|0) = var(x0) I (eq. 7)
      starts[m] = &start[m];
      q[m] = results[i].q;
      r[m] = results[i].r;
      limit = std::max(limit, std::min(n, options[i].max_time_varying_steps + 1));
    }
    fixed_order::WithWideFixedOrder(p, [&](auto order) {
      constexpr int kP = decltype(order)::value;
      if constexpr (kP > 0) {
        owner->push_back(std::make_unique<LaneGainTape<kP>>(starts, phi, q, r, active, limit));
      }
    });
    for (int m = 0; m < active; ++m) tapes[eligible[first + m]] = {owner->back().get(), m};
  }
  return tapes;
}

}  // namespace

ArFilterBank::ArFilterBank(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
                           double innovation_variance, double white_noise_variance,
                           const std::vector<ArKalmanOptions>& options,
                           const double* given_z_variance)
    : z_(z.data()), n_(z.size()), phi_(phi), filters_(options.size()) {
  double z_variance = 0.0;
  const bool z_ok =
      z.size() > 0 && (given_z_variance != nullptr ? (z_variance = *given_z_variance, true)
                                                   : SampleVarianceIfFinite(z, &z_variance));
  std::vector<PhaseEnd> ends(options.size());
  std::vector<bool> lane(options.size(), false);
  lanes_start_ = 0;
  std::vector<ArKalmanResult> results(options.size());
  std::vector<DareSolution> dares(options.size());
  std::vector<bool> prepared(options.size(), false);
  for (std::size_t i = 0; i < options.size(); ++i) {
    prepared[i] = PrepareFilter(z, phi, innovation_variance, white_noise_variance, options[i],
                                !z_ok, &results[i], &dares[i], &z_variance);
  }
  // The time-varying phases' gain sequences, four filters at a time (kept until they are replayed).
  std::vector<std::unique_ptr<GainTape>> tape_storage;
  const std::vector<TapeLane> tapes =
      MakeGainTapes(phi, options, results, dares, prepared, z_variance, n_, &tape_storage);
  for (std::size_t i = 0; i < options.size(); ++i) {
    Filter& f = filters_[i];
    ArKalmanResult& result = results[i];
    const DareSolution& dare = dares[i];
    if (!prepared[i]) {
      f.summary = std::move(result.summary);
      continue;
    }
    f.mean = options[i].mean;
    if (options[i].smooth) {
      // The smoother needs the whole series: FilterAr's path, kept as the head.
      RunFilter(z, phi, options[i], dare, z_variance, &result, nullptr);
      f.summary = std::move(result.summary);
      if (HasResult(f.summary.termination)) {
        f.head.assign(result.smoothed.data(), result.smoothed.data() + n_);
      }
      continue;
    }
    if (options[i].max_time_varying_steps > 0)  // the phase's longest output, without regrowing
      f.head.reserve(static_cast<std::size_t>(std::min(n_, options[i].max_time_varying_steps + 1)));
    ends[i] = RunTimeVaryingPhase(
        z, phi, options[i], dare, z_variance, &result,
        [&](long long, double estimate, double, const double*, double) {
          f.head.push_back(estimate);
        },
        tapes[i]);
    f.summary = std::move(result.summary);
    FinishSummary(options[i], dare, ends[i].zero_covariance, &f.summary);
    if (ends[i].k < n_) {
      lane[i] = true;
      lanes_start_ = std::max(lanes_start_, ends[i].k);
    }
  }
  // Every constant-gain filter continues alone up to the latest switch, then all side by side.
  const int p = static_cast<int>(phi.size());
  for (std::size_t i = 0; i < options.size(); ++i) {
    Filter& f = filters_[i];
    std::string unstable;
    if (lane[i] && HasResult(f.summary.termination) &&
        !ConstantGainLoopIsStable(phi_, ends[i], &unstable)) {
      f.summary.termination = Termination::kNumericalFailure;
      f.summary.message = unstable;
      f.summary.loop_unstable = true;
      f.head.clear();
      lane[i] = false;
    }
    if (lane[i]) {
      f.gain = std::move(ends[i].constant_gain);
      f.partial.resize(static_cast<std::size_t>(p));
      PartialPredictions(phi_, ends[i].x, f.partial.data());
      const long long k = ends[i].k;
      f.head.resize(static_cast<std::size_t>(lanes_start_));
      SteadyStateFilterFromPartial(z_ + k, lanes_start_ - k, f.mean, phi_, f.gain, f.partial.data(),
                                   f.head.data() + k, nullptr);
    }
    if (!HasResult(f.summary.termination)) continue;
    // The constant-gain loops are stable (G_inf stabilizes, a frozen gain is checked) and z is
    // finite, so only the time-varying head can overflow.
    if (!std::all_of(f.head.begin(), f.head.end(), [](double v) { return std::isfinite(v); })) {
      f.summary.termination = Termination::kNumericalFailure;
      f.summary.message = "non-finite filter output";
      f.head.clear();
      lane[i] = false;
    }
    f.lane = lane[i];
  }
}

void ArFilterBank::AddRange(long long begin, long long end, const std::vector<double*>& sums,
                            long long sum_stride, long long sum_origin) {
  std::vector<SteadyStateLane> lanes;
  const long long lanes_begin = std::max(begin, lanes_start_);
  for (std::size_t i = 0; i < filters_.size(); ++i) {
    Filter& f = filters_[i];
    if (!HasResult(f.summary.termination)) continue;
    const long long head_end = std::min<long long>(end, static_cast<long long>(f.head.size()));
    for (long long k = begin; k < head_end; ++k) {
      sums[i][(k - sum_origin) * sum_stride] += f.head[k];
      f.square_sum += (f.head[k] - f.mean) * (f.head[k] - f.mean);
    }
    if (f.lane && lanes_begin < end) {
      lanes.push_back({&f.gain, f.mean, sums[i] + (lanes_begin - sum_origin) * sum_stride,
                       f.partial.data(), &f.square_sum, sum_stride});
    }
  }
  if (!lanes.empty()) AddSteadyStateFilters(z_ + lanes_begin, end - lanes_begin, phi_, lanes);
  added_ += end - begin;
}

std::vector<double> ArFilterBank::EstimateMeanSquares() const {
  std::vector<double> out;
  for (const Filter& f : filters_) {
    out.push_back(HasResult(f.summary.termination) && added_ > 0
                      ? f.square_sum / static_cast<double>(added_)
                      : std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

bool FilterInputVariance(const Eigen::Ref<const Eigen::VectorXd>& z, double* variance) {
  return z.size() > 0 && SampleVarianceIfFinite(z, variance);
}

std::vector<ArKalmanSummary> ArFilterBank::summaries() const {
  std::vector<ArKalmanSummary> out;
  for (const Filter& f : filters_) out.push_back(f.summary);
  return out;
}

std::vector<ArKalmanSummary> FilterArAndAdd(const Eigen::Ref<const Eigen::VectorXd>& z,
                                            const Eigen::VectorXd& phi, double innovation_variance,
                                            double white_noise_variance,
                                            const std::vector<ArKalmanOptions>& options,
                                            const std::vector<double*>& sums) {
  ArFilterBank bank(z, phi, innovation_variance, white_noise_variance, options);
  bank.AddRange(0, z.size(), sums);
  return bank.summaries();
}

}  // namespace fogpipe::kalman
