#include "algorithms/ar/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/ar/autocorrelation.h"
#include "algorithms/common/chi_square.h"
#include "algorithms/common/fixed_order.h"
#include "algorithms/kernels/kernels.h"

namespace fogpipe::ar {
namespace {

constexpr Eigen::Index kBlock = 4096;
constexpr double kSmallestNormal = std::numeric_limits<double>::min();

// ||y - mean(y)||^2 for y = x_t, t = p..N-1.
double CenteredEnergy(const Eigen::Ref<const Eigen::VectorXd>& y) {
  const double m = y.mean();
  return (y.array() - m).square().sum();
}

// Sum of squares in four interleaved parts (element i of the whole series to part i % 4), so the
// order of the additions depends neither on the data's address (as Eigen's reductions do, which
// peel an unaligned head) nor on how the series is handed over, in pieces whose lengths are
// multiples of four: the blockwise one-step error energy and the whole residual vector's agree to
// the last bit.
class SquareSum {
 public:
  void Add(const double* v, Eigen::Index len) {
    Eigen::Index i = 0;
    for (; i + 4 <= len; i += 4) {
      for (int k = 0; k < 4; ++k) part_[k] += v[i + k] * v[i + k];
    }
    for (; i < len; ++i) tail_ += v[i] * v[i];
  }
  double Value() const { return ((part_[0] + part_[1]) + (part_[2] + part_[3])) + tail_; }

 private:
  double part_[4] = {0.0, 0.0, 0.0, 0.0};
  double tail_ = 0.0;
};

double FitPercent(double error_energy, double centered_energy) {
  if (!std::isfinite(error_energy)) return -std::numeric_limits<double>::infinity();
  return 100.0 * (1.0 - std::sqrt(error_energy / centered_energy));
}

// The residuals of samples [t0, t0 + len) into out: e_t = (x_t - mean) - sum_i phi_i (x_{t-i} -
// mean), the terms subtracted in order i = 1..p. Four samples at a time with the p taps in the
// inner loop (order P at compile time where it can), so each output is written once instead of
// once per tap; the same kernel alone or four at a time (kernels::ArResidual,
// algorithms/kernels/kernels.h), so every e_t has the same bits whatever its position in a
// vector.
template <int P>
FOGPIPE_LANE_KERNEL void ResidualBlock(const double* x, const double* phi_in, int p_runtime,
                                       double mean, Eigen::Index t0, Eigen::Index len,
                                       double* out) {
  const int p = P > 0 ? P : p_runtime;
  fixed_order::Buffer<P> phi_buffer(p);
  double* phi = phi_buffer.get();
  for (int i = 0; i < p; ++i) phi[i] = phi_in[i];
  Eigen::Index k = 0;
  for (; k + 4 <= len; k += 4) {
    const double* xt = x + t0 + k;
    kernels::StoreLanes4(out + k,
                         kernels::ArResidual<kernels::Lanes4>(
                             [xt](int i) { return kernels::LoadLanes4(xt - i); }, phi, p, mean));
  }
  for (; k < len; ++k) {
    const double* xt = x + t0 + k;
    out[k] = kernels::ArResidual<double>([xt](int i) { return xt[-i]; }, phi, p, mean);
  }
}

void OneStepResidualBlock(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model,
                          Eigen::Index t0, Eigen::Index len, double* out) {
  fixed_order::WithWideFixedOrder(model.order, [&](auto order) {
    constexpr int kP = decltype(order)::value;
    ResidualBlock<kP>(x.data(), model.phi.data(), model.order, model.mean, t0, len, out);
  });
}

/// OneStepResiduals into out[0 .. N - p).
void OneStepResidualsInto(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model,
                          double* out) {
  const Eigen::Index n = x.size();
  const int p = model.order;
  // Block by block (ResidualBlock: four samples at a time, every output written once).
  for (Eigen::Index t0 = p; t0 < n; t0 += kBlock)
    OneStepResidualBlock(x, model, t0, std::min(kBlock, n - t0), out + (t0 - p));
}

}  // namespace

Eigen::VectorXd OneStepResiduals(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model) {
  Eigen::VectorXd e(std::max<Eigen::Index>(x.size() - model.order, 0));
  OneStepResidualsInto(x, model, e.data());
  return e;
}

namespace {

// One per free run: each lane computes exactly what it would compute alone, whatever the others
// do (kernels::FreeRunSample, algorithms/kernels/kernels.h).
constexpr int kLanes = 4;
using Lanes = kernels::Lanes4;

// sum_t ((x_t - mean) - s_t)^2, t = p..N-1, for the free runs s_t of up to four models of the same
// order p, each on its own series of n samples (see the header): s_t = x_t - mean for t < p, then
// s_t = sum_i phi_i s_{t-i}. The last p values are kept in h[0..p-1] = s_{t-1}..s_{t-p}; phi_0
// s_{t-1} is added last, so the loop-carried chain is one multiply-add per sample and the older
// terms are off it. The runs step side by side in the lanes of one vector: a lone free run is bound
// by the latency of that chain, four of them cost about the same (measured on a sweep's 176 models:
// 3x faster than one run at a time, which was 4x faster than a runtime-order loop). P > 0: the
// order at compile time (loops unrolled, h in registers). Lanes beyond `count` run on zeros.
//
// Gradual underflow: a stable model's free response decays geometrically and, unless rounded to
// 0, can spend the rest of the record as subnormal numbers (measured on a 1 h 100 Hz sweep: the
// free runs of most components subnormal for 60-99 % of the record, often in a limit cycle that
// never reaches 0). Once all p values of a run's state are below the smallest normal double
// (checked every kBlock samples), they are set to 0: the rest of that free run would stay within a
// constant factor of 2.2e-308 for a stable model and could not change d = (x_t - mean) - s_t
// unless |x_t - mean| < 2^53 x 2.2e-308. From then on it is exactly 0. A lane's value does not
// depend on the lane it runs in or on the other lanes (tested).
template <int P>
FOGPIPE_LANE_KERNEL void FreeRunErrorEnergies(const SimulationFitJob* jobs, int count,
                                              int p_runtime, Eigen::Index n, double* energies) {
  const int p = P > 0 ? P : p_runtime;
  const double* x[kLanes];
  fixed_order::Buffer<P, Lanes> phi_buffer(p), h_buffer(p);
  Lanes* phi = phi_buffer.get();
  Lanes* h = h_buffer.get();
  Lanes mean = {};
  for (int i = 0; i < p; ++i) phi[i] = h[i] = Lanes{};
  static const double kZeros[1] = {0.0};
  for (int m = 0; m < kLanes; ++m) {
    x[m] = kZeros;
    if (m >= count) continue;
    const ArModel& model = *jobs[m].model;
    x[m] = jobs[m].x;
    mean[m] = model.mean;
    for (int i = 0; i < p; ++i) {
      phi[i][m] = model.phi[i];
      h[i][m] = x[m][p - 1 - i] - model.mean;
    }
  }
  const Eigen::Index x_step[kLanes] = {count > 0, count > 1, count > 2, count > 3};
  Lanes error_energy = {};
  Eigen::Index t = p;
  bool decayed[kLanes] = {count <= 0, count <= 1, count <= 2, count <= 3};
  while (t < n) {
    const Eigen::Index end = std::min(n, t + kBlock);
    for (; t < end; ++t) {
      const Lanes s = kernels::FreeRunSample(phi, p, h);
      const Lanes xt = {x[0][t * x_step[0]], x[1][t * x_step[1]], x[2][t * x_step[2]],
                        x[3][t * x_step[3]]};
      const Lanes d = xt - mean - s;
      error_energy += d * d;
    }
    bool all_decayed = true;
    for (int m = 0; m < kLanes; ++m) {
      if (!decayed[m]) {
        bool tiny = true;
        for (int i = 0; i < p; ++i) tiny = tiny && std::fabs(h[i][m]) < kSmallestNormal;
        if (tiny) {
          for (int i = 0; i < p; ++i) h[i][m] = 0.0;
          decayed[m] = true;
        }
      }
      all_decayed = all_decayed && decayed[m];
    }
    if (all_decayed) break;
  }
  for (; t < n; ++t) {  // every free run is exactly 0: d = (x_t - mean) - 0
    const Lanes xt = {x[0][t * x_step[0]], x[1][t * x_step[1]], x[2][t * x_step[2]],
                      x[3][t * x_step[3]]};
    const Lanes d = xt - mean - Lanes{};
    error_energy += d * d;
  }
  for (int m = 0; m < count; ++m) energies[m] = error_energy[m];
}

}  // namespace

double SimulationFitPercent(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model) {
  return SimulationFitPercents({{x.data(), x.size(), &model}}).front();
}

std::vector<double> SimulationFitPercents(const std::vector<SimulationFitJob>& jobs) {
  std::vector<double> fit(jobs.size(), std::numeric_limits<double>::quiet_NaN());
  // Jobs of equal order and length, four at a time in job order.
  std::vector<bool> done(jobs.size(), false);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    if (done[i]) continue;
    std::vector<std::size_t> group = {i};
    for (std::size_t j = i + 1; j < jobs.size() && group.size() < kLanes; ++j) {
      if (!done[j] && jobs[j].model->order == jobs[i].model->order && jobs[j].n == jobs[i].n)
        group.push_back(j);
    }
    std::vector<SimulationFitJob> lanes;
    for (std::size_t j : group) lanes.push_back(jobs[j]), done[j] = true;
    const int p = jobs[i].model->order;
    const Eigen::Index n = jobs[i].n;
    double lane_energy[kLanes];
    if (p == 0) {
      for (std::size_t m = 0; m < lanes.size(); ++m) {
        const Eigen::Map<const Eigen::VectorXd> x(lanes[m].x, n);
        lane_energy[m] = (x.array() - lanes[m].model->mean).square().sum();
      }
    } else {
      fixed_order::WithWideFixedOrder(p, [&](auto order) {
        constexpr int kP = decltype(order)::value;
        FreeRunErrorEnergies<kP>(lanes.data(), static_cast<int>(lanes.size()), p, n, lane_energy);
      });
    }
    for (std::size_t m = 0; m < group.size(); ++m) {
      const Eigen::Map<const Eigen::VectorXd> x(lanes[m].x, n);
      fit[group[m]] =
          FitPercent(lane_energy[m], lanes[m].centered_energy >= 0.0 ? lanes[m].centered_energy
                                                                     : CenteredTailEnergy(x, p));
    }
  }
  return fit;
}

namespace {

// Ljung-Box from the lagged products c(0..>=lag) of the n centred residuals.
LjungBoxTest LjungBoxFromLaggedProducts(const Eigen::VectorXd& c, Eigen::Index n, int lag,
                                        int num_params) {
  LjungBoxTest out;
  out.dof = std::max(lag - num_params, 1);
  if (n <= lag + 1 || !(c(0) > 0.0)) {
    out.statistic = out.p_value = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  const double nd = static_cast<double>(n);
  double q = 0.0;
  for (int k = 1; k <= lag; ++k) {
    const double rk = c(k) / c(0);
    q += rk * rk / (nd - k);
  }
  out.statistic = nd * (nd + 2.0) * q;
  out.p_value = LjungBoxPValue(out.statistic, out.dof);
  return out;
}

}  // namespace

bool FreeRunDiverged(double fit_simulation_percent) {
  return !std::isfinite(fit_simulation_percent) ||
         fit_simulation_percent <= kFreeRunDivergedPercent;
}

double LjungBoxPValue(double statistic, double dof) {
  return stats::ChiSquareSurvival(statistic, dof);
}

LjungBoxTest LjungBox(const Eigen::Ref<const Eigen::VectorXd>& residuals, int lag, int num_params) {
  const Eigen::VectorXd centered = residuals.array() - residuals.mean();
  return LjungBoxFromLaggedProducts(LaggedProducts(centered, std::max(lag, 0)), residuals.size(),
                                    lag, num_params);
}

double CenteredTailEnergy(const Eigen::Ref<const Eigen::VectorXd>& x, int p) {
  return CenteredEnergy(x.tail(x.size() - p));
}

double OneStepFitPercent(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model,
                         double centered_energy) {
  // The error energy block by block, without the residual vector (kBlock is a multiple of 4).
  const Eigen::Index n = x.size();
  std::vector<double> block(static_cast<std::size_t>(std::min(kBlock, n)));
  SquareSum error_energy;
  for (Eigen::Index t0 = model.order; t0 < n; t0 += kBlock) {
    const Eigen::Index len = std::min(kBlock, n - t0);
    OneStepResidualBlock(x, model, t0, len, block.data());
    error_energy.Add(block.data(), len);
  }
  return FitPercent(error_energy.Value(),
                    centered_energy >= 0.0 ? centered_energy : CenteredTailEnergy(x, model.order));
}

ArDiagnostics ComputeDiagnostics(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model) {
  Eigen::VectorXd scratch(x.size());
  return ComputeDiagnostics(x, model, scratch.data());
}

ArDiagnostics ComputeDiagnostics(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model,
                                 double* scratch) {
  ArDiagnostics d;
  const int p = model.order;
  Eigen::Map<Eigen::VectorXd> e(scratch, std::max<Eigen::Index>(x.size() - p, 0));
  OneStepResidualsInto(x, model, e.data());
  SquareSum sum;
  sum.Add(e.data(), e.size());
  const double error_energy = sum.Value();
  d.fit_one_step_percent = FitPercent(error_energy, CenteredTailEnergy(x, p));
  d.fit_simulation_percent = SimulationFitPercent(x, model);
  d.residual_variance = error_energy / static_cast<double>(e.size());
  // Both Ljung-Box lags from one pass of lagged products over the residuals, centred in place.
  e.array() -= e.mean();
  const Eigen::VectorXd c = LaggedProducts(e, 20);
  const LjungBoxTest lb10 = LjungBoxFromLaggedProducts(c, e.size(), 10, p);
  const LjungBoxTest lb20 = LjungBoxFromLaggedProducts(c, e.size(), 20, p);
  d.ljung_box_q10 = lb10.statistic;
  d.ljung_box_p10 = lb10.p_value;
  d.ljung_box_q20 = lb20.statistic;
  d.ljung_box_p20 = lb20.p_value;
  return d;
}

}  // namespace fogpipe::ar
