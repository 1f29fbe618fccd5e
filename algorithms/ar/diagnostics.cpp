#include "algorithms/ar/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/allan/chi_square.h"
#include "algorithms/ar/autocorrelation.h"

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
  const Eigen::Index n = x.size();
  const int p = model.order;
  // The free run s_t is written into a window of kBlock + p samples; each window's last p samples
  // seed the next, so the history is always contiguous and memory stays O(kBlock).
  std::vector<double> window(kBlock + p);
  for (int i = 0; i < p; ++i) window[i] = x(i) - model.mean;
  const double* phi = model.phi.data();
  double error_energy = 0.0;
  // s_{t-1} is kept in a register: the loop-carried chain is then one multiply-add per sample, the
  // older terms (read from the window) are off that chain. 4x faster than summing from memory.
  double prev = p > 0 ? window[p - 1] : 0.0;
  for (Eigen::Index t0 = p; t0 < n; t0 += kBlock) {
    const Eigen::Index len = std::min(kBlock, n - t0);
    for (Eigen::Index j = 0; j < len; ++j) {
      double older = 0.0;
      const double* past = &window[j + p - 1];  // s_{t-1}; s_{t-i} = past[1 - i]
      for (int i = 1; i < p; ++i) older += phi[i] * past[-i];
      const double s = p > 0 ? phi[0] * prev + older : 0.0;
      prev = s;
      window[j + p] = s;
      const double d = x(t0 + j) - model.mean - s;
      error_energy += d * d;
    }
    std::copy(window.begin() + len, window.begin() + len + p, window.begin());
  }
  return FitPercent(error_energy, CenteredEnergy(x.tail(n - p)));
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
  return 1.0 - allan::ChiSquareCdf(statistic, dof);
}

LjungBoxTest LjungBox(const Eigen::Ref<const Eigen::VectorXd>& residuals, int lag, int num_params) {
  const Eigen::VectorXd centered = residuals.array() - residuals.mean();
  return LjungBoxFromLaggedProducts(LaggedProducts(centered, std::max(lag, 0)), residuals.size(),
                                    lag, num_params);
}

ArDiagnostics ComputeDiagnostics(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model) {
  ArDiagnostics d;
  const Eigen::Index n = x.size();
  const int p = model.order;
  Eigen::VectorXd e = OneStepResiduals(x, model);
  const double centered = CenteredEnergy(x.tail(n - p));
  const double error_energy = e.squaredNorm();
  d.fit_one_step_percent = FitPercent(error_energy, centered);
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
