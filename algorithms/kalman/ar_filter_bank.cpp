#include "algorithms/kalman/ar_filter_bank.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "algorithms/common/fixed_order.h"
#include "algorithms/kalman/covariance_recursion.h"
#include "algorithms/kalman/filter_phases.h"
#include "algorithms/kalman/steady_state_filter.h"

namespace fogpipe::kalman {

using internal::ConstantGainLoopIsStable;
using internal::CovarianceLanes;
using internal::CovarianceLanes4;
using internal::DecidePhaseStart;
using internal::FinishSummary;
using internal::PhaseEnd;
using internal::PhaseStart;
using internal::PrepareFilter;
using internal::RunFilter;
using internal::RunTimeVaryingPhase;
using internal::SampleVarianceIfFinite;

namespace {

// The gain sequences G(k) and innovation variances S(k) of up to four time-varying filters of one
// AR model, computed side by side (CovarianceLanes) on demand, a chunk of steps at a
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
      const CovarianceLanes4 s = lanes_.Step();
      const CovarianceLanes4* g = lanes_.gain();
      for (int m = 0; m < active_; ++m) {
        variances_[m].push_back(s[m]);
        for (int i = 0; i < P; ++i) gains_[m].push_back(g[i][m]);
      }
    }
  }

 private:
  CovarianceLanes<P> lanes_;
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
        [&](auto order, auto&& run) {
          constexpr int kP = decltype(order)::value;
          if constexpr (kP > 0) {
            if (tapes[i].tape != nullptr) {
              run(ReplayedRecursion<kP>(tapes[i].tape, tapes[i].lane));
              return true;
            }
          }
          return false;
        });
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
