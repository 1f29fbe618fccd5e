// The reference filters side by side on one signal, each tuned without the truth: the simple
// alternatives a gyro engineer would use instead of the paper's method, run and stored beside
// methods 1 and 2 so that every result shows whether the method helps.
//
//   butterworth     zero-phase Butterworth low-pass, cutoff by GCV (butterworth.h)
//   moving_average  centred moving average, window by GCV (moving_average.h)
//   rw_kalman       random-walk-rate Kalman filter, q and R by maximum likelihood (causal)
//   rw_rts          its RTS smoother (random_walk_kalman.h)
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "algorithms/common/for_each.h"
#include "algorithms/common/status.h"
#include "algorithms/filters/butterworth.h"
#include "algorithms/filters/moving_average.h"
#include "algorithms/filters/random_walk_kalman.h"

namespace fogpipe::filters {

struct ReferenceFilterOptions {
  /// Run the reference filters at all. Default true.
  bool enabled = true;
  ButterworthOptions butterworth;
  MovingAverageOptions moving_average;
  RandomWalkKalmanOptions random_walk;

  bool IsValid(std::string* error) const;
};

/// One reference filter's output and its tuning.
struct ReferenceOutput {
  std::string name;        ///< "butterworth", "moving_average", "rw_kalman", "rw_rts"
  Eigen::VectorXd signal;  ///< filtered input, units of the input
  /// The tuned parameter: cutoff (Hz), window (samples), q / R (1); its name and units.
  std::string parameter_name, parameter_units;
  double parameter = 0.0;
  /// "" or why the tuning is at the edge of its range (e.g. GCV chose the widest window).
  std::string note;
  Termination termination = Termination::kInvalidOptions;
  std::string message;
};

/// The names in output order.
const std::vector<std::string>& ReferenceFilterNames();

/// Runs every reference filter on x (the RTS smoother comes with the Kalman filter). Returns
/// ReferenceFilterNames().size() outputs in that order, or none when !options.enabled.
/// The tunings are independent and run as four tasks (the Butterworth, the random-walk filters,
/// the moving average, then `beside`: other work of the caller's, may be empty; also run when
/// !options.enabled), handed out in that order to two lanes through for_each, so at most two run
/// at once. The Butterworth's GCV spectrum is the largest transient (about 3.5 N doubles while its
/// FFT runs); which task it meets depends on the schedule (docs/performance.md). The outputs do
/// not depend on the lanes.
std::vector<ReferenceOutput> RunReferenceFilters(const Eigen::VectorXd& x, double sample_rate_hz,
                                                 const ReferenceFilterOptions& options,
                                                 const ForEach& for_each,
                                                 const std::function<void()>& beside = nullptr);

}  // namespace fogpipe::filters
