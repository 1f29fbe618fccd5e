#include "algorithms/ar/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/ar/autocorrelation.h"
#include "algorithms/common/chi_square.h"

namespace fogpipe::ar {
namespace {

constexpr Eigen::Index kBlock = 4096;

// ||y - mean(y)||^2 for y = x_t, t = p..N-1.
double CenteredEnergy(const Eigen::Ref<const Eigen::VectorXd>& y) {
  const double m = y.mean();
  return (y.array() - m).square().sum();
}

double FitPercent(double error_energy, double centered_energy) {
  if (!std::isfinite(error_energy)) return -std::numeric_limits<double>::infinity();
  return 100.0 * (1.0 - std::sqrt(error_energy / centered_energy));
}

}  // namespace

Eigen::VectorXd OneStepResiduals(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model) {
  const Eigen::Index n = x.size();
  const int p = model.order;
  Eigen::VectorXd e(std::max<Eigen::Index>(n - p, 0));
  // Block-wise axpys so each block of x is reused p times from cache.
  for (Eigen::Index t0 = p; t0 < n; t0 += kBlock) {
    const Eigen::Index len = std::min(kBlock, n - t0);
    auto out = e.segment(t0 - p, len);
    out = x.segment(t0, len).array() - model.mean;
    for (int i = 1; i <= p; ++i)
      out.array() -= model.phi(i - 1) * (x.segment(t0 - i, len).array() - model.mean);
  }
  return e;
}

double SimulationFitPercent(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model) {
  return SimulationFitPercents(x, {&model}).front();
}

std::vector<double> SimulationFitPercents(const Eigen::Ref<const Eigen::VectorXd>& x,
                                          const std::vector<const ArModel*>& models) {
  // Each model's free run s_t is written into its own window of kBlock + p samples; each window's
  // last p samples seed the next, so the history is always contiguous and memory stays O(kBlock).
  // s_{t-1} is kept in `prev`: the loop-carried chain is then one multiply-add per sample, the
  // older terms (read from the window) are off that chain. The models step together per sample
  // (samples outside, models inside): their chains are independent, so the CPU overlaps them,
  // and each model still sees exactly the operations it would see alone.
  struct FreeRun {
    const double* phi = nullptr;
    int p = 0;
    double mean = 0.0, prev = 0.0, error_energy = 0.0;
    Eigen::Index j = 0;  // position in the current block
    std::vector<double> window;
  };
  const Eigen::Index n = x.size();
  std::vector<FreeRun> runs;
  runs.reserve(models.size());
  Eigen::Index first = n;
  for (const ArModel* model : models) {
    FreeRun r;
    r.phi = model->phi.data();
    r.p = model->order;
    r.mean = model->mean;
    r.window.assign(kBlock + r.p, 0.0);
    for (int i = 0; i < r.p; ++i) r.window[i] = x(i) - r.mean;
    r.prev = r.p > 0 ? r.window[r.p - 1] : 0.0;
    first = std::min<Eigen::Index>(first, r.p);
    runs.push_back(std::move(r));
  }
  for (Eigen::Index t = first; t < n; ++t) {
    const double xt = x(t);
    for (FreeRun& r : runs) {
      if (t < r.p) continue;
      const int p = r.p;
      double older = 0.0;
      const double* past = &r.window[r.j + p - 1];  // s_{t-1}; s_{t-i} = past[1 - i]
      for (int i = 1; i < p; ++i) older += r.phi[i] * past[-i];
      const double s = p > 0 ? r.phi[0] * r.prev + older : 0.0;
      r.prev = s;
      r.window[r.j + p] = s;
      const double d = xt - r.mean - s;
      r.error_energy += d * d;
      if (++r.j == kBlock) {
        std::copy(r.window.begin() + kBlock, r.window.begin() + kBlock + p, r.window.begin());
        r.j = 0;
      }
    }
  }
  std::vector<double> fit;
  fit.reserve(runs.size());
  for (const FreeRun& r : runs)
    fit.push_back(FitPercent(r.error_energy, CenteredEnergy(x.tail(n - r.p))));
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

double LjungBoxPValue(double statistic, double dof) {
  return stats::ChiSquareSurvival(statistic, dof);
}

LjungBoxTest LjungBox(const Eigen::Ref<const Eigen::VectorXd>& residuals, int lag, int num_params) {
  const Eigen::VectorXd centered = residuals.array() - residuals.mean();
  return LjungBoxFromLaggedProducts(LaggedProducts(centered, std::max(lag, 0)), residuals.size(),
                                    lag, num_params);
}

double OneStepFitPercent(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model) {
  return FitPercent(OneStepResiduals(x, model).squaredNorm(),
                    CenteredEnergy(x.tail(x.size() - model.order)));
}

ArDiagnostics ComputeDiagnostics(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model) {
  ArDiagnostics d;
  const int p = model.order;
  Eigen::VectorXd e = OneStepResiduals(x, model);
  const double error_energy = e.squaredNorm();
  d.fit_one_step_percent = FitPercent(error_energy, CenteredEnergy(x.tail(x.size() - p)));
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
