// Model adequacy: fit percentages, residual variance and the Ljung-Box portmanteau test.
//
// Fit (MATLAB `compare`; the paper's eq. 3 without its missing "1 -"):
//   fit = 100 (1 - ||y - yhat|| / ||y - mean(y)||),
// over samples t = p..N-1 (the first p samples are needed as the predictor's history), y = x_t
// and mean(y) over the same samples.
//   One-step: yhat_t = mean + sum phi_i (x_{t-i} - mean), i.e. y - yhat is the innovation sequence.
//     For a stationary AR(1) with coefficient phi this tends to 100 (1 - sqrt(1 - phi^2)).
//   Simulation: yhat_t = mean + s_t with s_t = x_t - mean for t < p (the first p samples are the
//     initial state) and s_t = sum phi_i s_{t-i} for t >= p: no noise, no further data. A
//     noise-free signal that obeys the model gives 100; for a noise-driven stationary process the
//     free response decays to the mean and the fit tends to 0 (slightly above it). A non-stationary
//     model whose simulation overflows gives -inf.
// Ljung-Box (Ljung & Box 1978): Q(h) = n (n + 2) sum_{k=1}^{h} r_k^2 / (n - k) on the n one-step
// residuals, r_k their sample autocorrelation (mean removed); p-value = P(chi2_{h-p} > Q), the
// degrees of freedom h - p clamped to >= 1. The chi-square tail is ChiSquareSurvival from
// algorithms/common/chi_square.h (regularized incomplete gamma, Numerical Recipes gser/gcf), shared
// rather than written twice; as a complement it is accurate to ~1e-15 absolute, so p-values below
// that read as 0 (R's Box.test prints "< 2.2e-16" for the same reason).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "algorithms/ar/ar_model.h"

namespace fogpipe::ar {

struct ArDiagnostics {
  double fit_one_step_percent = 0.0;    ///< One-step-ahead fit, % (see the file comment).
  double fit_simulation_percent = 0.0;  ///< Free-run (simulation) fit, %.
  double residual_variance = 0.0;       ///< Mean square of the one-step residuals, units of x^2.
  double ljung_box_q10 = 0.0;           ///< Ljung-Box statistic at lag 10 (dimensionless).
  double ljung_box_p10 = 0.0;           ///< Its p-value, chi-square with max(10 - p, 1) dof.
  double ljung_box_q20 = 0.0;           ///< Ljung-Box statistic at lag 20.
  double ljung_box_p20 = 0.0;           ///< Its p-value, chi-square with max(20 - p, 1) dof.
};

struct LjungBoxTest {
  double statistic = 0.0;
  double p_value = 0.0;
  int dof = 0;
};

/// Innovations e_t = (x_t - mean) - sum phi_i (x_{t-i} - mean), t = p..N-1 (size N - p).
Eigen::VectorXd OneStepResiduals(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model);

/// Free-run fit percentage (see the file comment).
double SimulationFitPercent(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model);

/// A free-run fit to compute: `model` scored on the n samples at x (contiguous, outliving the
/// call).
struct SimulationFitJob {
  const double* x = nullptr;
  Eigen::Index n = 0;
  const ArModel* model = nullptr;
  /// CenteredTailEnergy of x at the model's order if the caller has it, else negative.
  double centered_energy = -1.0;
};

/// The free-run fit percentage of every job; each job's value does not depend on the others
/// (SimulationFitPercent is this with one job). Jobs of the same order and length run side by side,
/// four at a time: a sweep scores one AR order of all components this way.
std::vector<double> SimulationFitPercents(const std::vector<SimulationFitJob>& jobs);

/// Free-run fits at or below this have diverged: fit <= -1000 % means ||y - yhat|| >= 11 ||y -
/// mean||, so by the triangle inequality the free response is at least 10 times as far from the
/// mean as the data (RMS), the ratio at which a Kalman estimate counts as diverged too
/// (method::kDivergedRmsRatio). A stationary model's free response starts from the data and decays;
/// one that ends ten times larger has grown. Tables print "diverged" instead of the number.
constexpr double kFreeRunDivergedPercent = -1000.0;

/// Whether a free-run fit percentage is a diverged one (non-finite or <= kFreeRunDivergedPercent).
bool FreeRunDiverged(double fit_simulation_percent);

/// P(chi2_dof > statistic): the Ljung-Box p-value for a statistic and its degrees of freedom.
double LjungBoxPValue(double statistic, double dof);

/// Ljung-Box test of `residuals` at lag `lag` for a model with `num_params` fitted coefficients.
LjungBoxTest LjungBox(const Eigen::Ref<const Eigen::VectorXd>& residuals, int lag, int num_params);

/// ||x_t - m||^2 over t = p..N-1, m the mean of those samples: the denominator of both fit
/// percentages of an AR(p) model.
double CenteredTailEnergy(const Eigen::Ref<const Eigen::VectorXd>& x, int p);

/// One-step fit percentage alone (no Ljung-Box, no residual vector), equal to ComputeDiagnostics'
/// to the last bit. centered_energy: CenteredTailEnergy(x, model.order) if the caller has it (a
/// sweep scores both fits of each order), else negative.
double OneStepFitPercent(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model,
                         double centered_energy = -1.0);

/// All of the above. Requires x.size() > model.order + 20.
ArDiagnostics ComputeDiagnostics(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model);
/// The same, with the residuals written to `scratch`, which must hold N doubles (a caller's work
/// array, so that no N-sized array is allocated here).
ArDiagnostics ComputeDiagnostics(const Eigen::Ref<const Eigen::VectorXd>& x, const ArModel& model,
                                 double* scratch);

}  // namespace fogpipe::ar
