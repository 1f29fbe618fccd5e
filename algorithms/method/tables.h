// The paper's Tables 3 (fit % per component) and 5 (Allan noise terms per signal) as plain rows,
// and their text rendering. `fogpipe run` fills them from a MethodResult, `fogpipe info` from a
// results file; both print them with the same functions.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

namespace fogpipe::method {

struct MethodResult;

/// One row of Table 3.
struct FitRow {
  std::string component;                ///< "raw (method 2)", "imf1", ..., "residue"
  int order = 0;                        ///< AR order p
  double fit_one_step_percent = 0.0;    ///< 100 (1 - ||y - yhat|| / ||y - mean y||), one step ahead
  double fit_simulation_percent = 0.0;  ///< the same with yhat simulated from the model
  /// With the smoother: its output was replaced by the filter's, the record contradicting the
  /// model in the smoother's direction (kalman::ArKalmanSummary::smoother_replaced).
  bool smoother_replaced = false;
};

/// One row of Table 5, in engineer's units (algorithms/common/units.h); NaN where not fitted.
struct NoiseRow {
  std::string signal;  ///< "raw", "method 1", "method 2", then the reference filters' names
  double q_arcsec = 0.0, n_deg_sqrt_h = 0.0, b_deg_h = 0.0, k_deg_h_sqrt_h = 0.0, r_deg_h2 = 0.0;
  /// Goodness of the noise fit (allan/noise_fit.h): chi2 / dof and its p-value [1]; NaN unknown.
  double chi2_per_dof = std::numeric_limits<double>::quiet_NaN();
  double p_value = std::numeric_limits<double>::quiet_NaN();
  /// Per term Q, N, B, K, R: why it is unreliable; empty when reliable (marked '*' in the table).
  std::array<std::string, 5> unreliable_reason{};
  /// Per term Q, N, B, K, R: the slope read-off (IEEE Std 952-1997 Annex C;
  /// allan::NoiseFitResult::slope_readoff) in the term's unit above; NaN where there is none.
  std::array<double, 5> readoff{
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::quiet_NaN()};
};

/// Table 3 rows: method 2's direct model first, then every IMF and the residue.
std::vector<FitRow> Table3(const MethodResult& result);
/// Table 5 rows: raw, method 1, method 2, then one row per reference filter
/// (filters::ReferenceFilterNames(): butterworth, moving_average, rw_kalman, rw_rts; NaN terms for
/// a filter that failed).
std::vector<NoiseRow> Table5(const MethodResult& result);

/// Fixed-width text, one header line and one line per row, units in the header.
std::string FormatTable3(const std::vector<FitRow>& rows);
std::string FormatTable5(const std::vector<NoiseRow>& rows);

}  // namespace fogpipe::method
