// The sweep's filter bank: one AR model filtered under many option sets (the q/R settings of
// `fogpipe sweep`) at once, each output equal to the paper's filter (FilterAr, ar_kalman.h) run
// alone, to the last bit. The bank runs FilterAr's steps (filter_phases.h) in another order: the
// time-varying phases' gains four filters at a time (gain tapes, replayed one filter after the
// other), then the constant-gain loops side by side (steady_state_filter.h).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "algorithms/kalman/ar_kalman.h"

namespace fogpipe::kalman {

/// One AR model filtered under several option sets (the q/R settings of a sweep) over the same z,
/// output i added to a sum range by range, so that a caller can interleave the banks of many
/// components over one cache-sized range of their sums at a time. Construction runs every
/// filter's start alone: PrepareFilter (options, noise levels, DARE) and its time-varying phase
/// (FilterAr's code); each filter that reaches a constant-gain loop at sample k_i continues alone
/// (SteadyStateFilterFromPartial) up to K = max_i k_i, and from K all of them run side by side
/// (AddSteadyStateFilters). Option sets with the smoother, or that never reach a constant gain,
/// are computed whole at construction. Output i equals FilterAr(z, phi, ..., options[i]).filtered
/// (its smoothed series when options[i].smooth) to the last bit: the same arithmetic in the same
/// order (tested). Memory: the time-varying heads (K doubles per filter; n for the others).
/// z must outlive the bank.
class ArFilterBank {
 public:
  /// z_variance: the sample variance of z if the caller has it from FilterInputVariance (banks of
  /// several AR orders over one z), else null.
  ArFilterBank(const Eigen::Ref<const Eigen::VectorXd>& z, const Eigen::VectorXd& phi,
               double innovation_variance, double white_noise_variance,
               const std::vector<ArKalmanOptions>& options, const double* z_variance = nullptr);
  /// Adds output i's sample k, for k in [begin, end), to sums[i][(k - sum_origin) * sum_stride]
  /// (sum_origin <= begin: a caller may keep only the current range of its sums). Successive calls
  /// must cover [0, n) in order (the side-by-side filters carry their state from one range to the
  /// next). A sum whose summary has no result is left untouched. Sums interleaved sample by
  /// sample (sums[i] = base + i, sum_stride = the number of sums) are added with vector
  /// operations, four sums at a time (steady_state_filter.h).
  void AddRange(long long begin, long long end, const std::vector<double*>& sums,
                long long sum_stride = 1, long long sum_origin = 0);
  std::vector<ArKalmanSummary> summaries() const;
  /// Output i's mean of (estimate - mean)^2 over the samples added so far, units of z^2 (NaN for a
  /// sum left untouched). A filter on a stationary model fitted to z estimates x with a variance
  /// below z's (var(x^) = var(x) - P <= var(z)); far above it, the filter has diverged (see
  /// method/sweep_evaluate.cpp).
  std::vector<double> EstimateMeanSquares() const;

 private:
  struct Filter {
    ArKalmanSummary summary;
    double mean = 0.0;
    std::vector<double> head;     ///< Outputs [0, head.size()).
    bool lane = false;            ///< Continued side by side from lanes_start_.
    Eigen::VectorXd gain;         ///< Constant gain of the side-by-side loop.
    std::vector<double> partial;  ///< Its loop state (steady_state_filter.h).
    double square_sum = 0.0;      ///< sum of (estimate - mean)^2 over the samples added
  };
  const double* z_;
  long long n_;
  Eigen::VectorXd phi_;
  std::vector<Filter> filters_;
  long long lanes_start_ = 0;
  long long added_ = 0;  ///< samples added so far
};

/// The sample variance of z as the filter computes it for its start P(0|0) (eq. 7); false if z has
/// a non-finite sample. For ArFilterBank's z_variance.
bool FilterInputVariance(const Eigen::Ref<const Eigen::VectorXd>& z, double* variance);

/// ArFilterBank over the whole series at once: output i added to sums[i][0..n). Returns the
/// summaries; a sum whose summary has no result is left untouched.
std::vector<ArKalmanSummary> FilterArAndAdd(const Eigen::Ref<const Eigen::VectorXd>& z,
                                            const Eigen::VectorXd& phi, double innovation_variance,
                                            double white_noise_variance,
                                            const std::vector<ArKalmanOptions>& options,
                                            const std::vector<double*>& sums);

}  // namespace fogpipe::kalman
