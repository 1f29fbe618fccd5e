// A parameter sweep on one axis (fogpipe sweep): the EMD runs once, then every setting
// of the grid (AR order x q scale x R scale) models and filters every component and is scored.
//
//   x --Preprocess + EMD (once)--> components c_1..c_K (IMFs and residue)
//   per component: one Burg recursion to the grid's largest order gives the models of every
//     lower order (Burg 1975; Kay & Marple 1981: the order-m model is a by-product of order m+1),
//     and each order's one-step and simulation fit % (Table 3's metric);
//   per setting (p, q_scale, r_scale; sweep_grid.h says what the scales refer to, and the default
//     rule of `fogpipe run` is one more setting per order): Kalman filter of every component on
//     its AR(p) model,
//     method 1 = sum of the filtered components (eq. 12, component order), its Allan table and
//     noise terms, and on simulated data the RMS error against the true rate.
//
// The AR orders run through `for_each` (the pipeline passes a tbb::parallel_for), and within an
// order the Allan evaluation of its settings too; every setting writes only its own slot and sums
// its components in component order, so the numbers do not depend on the schedule. All q/R
// settings of one order are filtered together (kalman::ArFilterBank): each filter's start (the
// time-varying phase of the paper's start, capped at 4096 steps in the sweep, sweep_evaluate.cpp
// says why) runs alone, then the constant-gain loops of all settings run side by side from their
// own states, four per vector register. Each setting's output equals kalman::FilterAr's for its
// options to the last bit (tested in ar_kalman_test). The method-1 sums are filled range by range
// (2048 samples of every setting and every component, in component order) so that they stay in
// cache. Memory: the decomposition plus one signal-length sum per setting of every order in
// flight (10 settings per order for a 3 x 3 grid: 29 MB per order for 1 h at 100 Hz) and one
// phase per Allan table in flight, kept between orders for reuse and released before the
// reference filters run, and the filters' time-varying heads (about 4096 doubles per setting and
// component).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/method/method.h"
#include "algorithms/method/sweep_grid.h"

namespace fogpipe::method {

struct SweepOptions {
  /// Preprocessing, EMD, Allan and noise-fit options, and the Kalman options the scales multiply
  /// (method.component.kalman; its q_scale and r_scale are replaced by the grid's).
  MethodOptions method;
  SweepGrid grid;

  bool IsValid(std::string* error) const;
};

/// The score of one setting.
struct SweepPoint {
  SweepSetting setting;
  /// Per component (IMFs then residue): fit % of its AR(p) model, one step ahead and simulated.
  std::vector<double> fit_one_step_percent;
  std::vector<double> fit_simulation_percent;
  /// Per component: the AR order its filter ran, the setting's order or the highest stationary
  /// order below it (ar::SelectStationaryOrder; 0 for a constant component passed through).
  std::vector<int> ar_order_used;
  /// Allan table and Q, N, B, K, R of the method-1 output (the filtered, reconstructed signal).
  AllanEvaluation allan;
  /// RMS of (method 1 + removed mean) - true rate over the analysed samples, units of the input;
  /// NaN without a truth.
  double rms_error = 0.0;
  /// Wall time of this setting, s: its share of its order's filtering and reconstruction (all
  /// settings of an order are filtered together), plus its own Allan and noise fit.
  double seconds = 0.0;
  Termination termination = Termination::kInvalidOptions;
  std::string message;
};

/// A reference filter (filters/reference_filters.h) scored like a grid setting, so that the
/// sweep ranks it with the grid: its point has Allan terms, the RMS error against the truth and
/// its time, but no AR setting or fit % (the "fit" criterion is NaN for it).
struct SweepReference {
  std::string name;  ///< "butterworth", "moving_average", "rw_kalman", "rw_rts"
  std::string parameter_name, parameter_units;  ///< the tuned parameter (reference_filters.h)
  double parameter = 0.0;
  SweepPoint point;
};

struct SweepSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  int num_imfs = 0;
  int settings_ok = 0;
  double decompose_seconds = 0.0;  ///< Preprocessing + EMD, s.
  double models_seconds = 0.0;     ///< Burg recursions and fit % of every component, s.
};

struct SweepResult {
  /// Preprocessing and decomposition (components, method1 and the Allan results stay empty).
  MethodResult base;
  /// One per grid setting, in GridSettings() order.
  std::vector<SweepPoint> points;
  /// The reference filters on the same preprocessed signal (empty when
  /// method.reference.enabled is false).
  std::vector<SweepReference> reference;
  SweepSummary summary;
};

/// Runs the sweep on one axis `x` (any rate unit) sampled at `sample_rate_hz`. `truth` (may be
/// nullptr): the true rate of every input sample, same units and length as x, for the RMS error.
SweepResult RunSweep(const Eigen::VectorXd& x, double sample_rate_hz, const SweepOptions& options,
                     const Eigen::VectorXd* truth, const ForEach& for_each = SerialForEach);

/// How many grid points rank strictly better than `reference` by `criterion` (its 0-based place
/// among the grid's ranking); -1 when its value is NaN.
int RankAmongGrid(const std::vector<SweepPoint>& points, const SweepPoint& reference,
                  const std::string& criterion);

/// Named ranking criteria: "rms_error", "q", "n", "b", "k", "r" (smaller is better) and "fit"
/// (mean one-step fit % over the components, larger is better).
const std::vector<std::string>& RankCriteria();
/// The value of `criterion` for a point (NaN when it has none). Throws std::invalid_argument for
/// an unknown criterion.
double CriterionValue(const SweepPoint& point, const std::string& criterion);
/// Indices of `points` with a result, best first by `criterion` (ties keep grid order); points
/// whose value is NaN come last.
std::vector<int> RankSweep(const std::vector<SweepPoint>& points, const std::string& criterion);

}  // namespace fogpipe::method
