// Several bias levels (catalog term bias_levels): a piecewise-constant bias with k jumps, and the
// jump test of the time view that shows such a bias where the Allan view cannot.
//
// Why. k jumps of the bias add to the Allan variance the law of a rate random walk (a single step
// D gives K^2 = D^2 / T, targeted_tests.h), and random telegraph switching (a bias jumping
// between two levels with exponential dwell times, Machlup 1954) has exactly the Lorentzian
// spectrum and Allan law of a first-order Gauss-Markov process of sigma a / 2 (a the level
// separation) and correlation time tau_d / 2 (tau_d the mean dwell). The second-order views
// (Allan, PSD) cannot tell them from those Gaussian terms; the distribution of the increments
// can: every stochastic term of the catalog is Gaussian, so the differences of adjacent window
// means of the residual are Gaussian under a right model whatever its power law, while jumps make
// them a mixture (most windows see no jump, a few see one whole), with excess kurtosis.
//
//   Jump test (IncrementKurtosisZ): the sample kurtosis b2 of the differences of adjacent,
//   non-overlapping window means at window lengths L = W / 2^j (W the time view's window,
//   j = 0..levels_scales-1), transformed to N(0, 1) under Gaussian data by Anscombe & Glynn
//   (1983). Adjacent differences of white-noise means are correlated (-1/2 at lag 1), which
//   multiplies the variance of b2 by 1 + 2 (1/2)^4 = 1.125 (the variance of a kurtosis estimate
//   of a Gaussian linear process, sum of rho(h)^4; Bartlett 1946 style), so z is divided by
//   sqrt(1.125). One-sided: only heavy tails are jumps.
//
//   Segmentation (SegmentLevels): binary segmentation (Scott & Knott 1974; Vostrikova 1981) of
//   the residual's block means (block_s), each split at the maximum of the CUSUM statistic of
//   its segment, up to max_steps; the number of steps k by the modified BIC of Zhang & Siegmund
//   (2007), n_eff ln RSS_k + 3 k ln n_eff (a size and a time per step, the time searched over the
//   record: 3 ln n per change point instead of 2), with n_eff = m / lambda, lambda the long-run
//   variance ratio of the residual at max_steps (the noise once every step-like structure is
//   removed; the same deflation of the sample count as the aux terms' order by BIC,
//   deterministic_fit.h). Then each step time is refined on the full-rate samples, within its
//   block and the neighbouring ones, by the exact two-segment least squares.
//
//   Telegraph reading (DescribeLevels): the fitted segment levels are split into two groups at
//   the largest gap of their sorted values; the switching is two-level when every level lies
//   within 3 standard errors (plus 10 % of the separation) of its group's mean and the levels
//   alternate between the groups at every step, and read as random telegraph switching from six
//   dwells on (fewer are a few steps that happen to return). Mean dwell = record / (k + 1),
//   the equivalent Gauss-Markov correlation time is dwell / 2 and sigma the half separation.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace fogpipe::model {

struct LevelsOptions {
  /// Block length of the segmentation, s (steps are refined to the sample afterwards).
  double block_s = 10.0;
  /// Penalty per step in units of ln n_eff (3: modified BIC, header comment).
  double penalty_per_step = 3.0;
  /// Batch length of the residual's variance ratio lambda, s, and the most re-segmentations.
  double lambda_batch_s = 60.0;
  int lambda_iterations = 4;
  /// lambda given (> 0: the noise model's, LevelsVarianceRatio) instead of estimated from the data.
  double variance_ratio = 0.0;
  /// Shortest segment, s.
  double min_segment_s = 20.0;
  bool IsValid(std::string* error) const;
};

/// The steps of a piecewise-constant fit: sample indices where the new level starts, ascending.
struct LevelsSegmentation {
  std::vector<long> step_index;
  double long_run_variance_ratio = 1.0;  ///< lambda of the block means' residual
  double short_run_variance = 0;         ///< of a block mean, (units of x)^2
  double gain = 0;     ///< -2 ln L drop of the steps (variance short_run_variance * lambda)
  double penalty = 0;  ///< per step: penalty_per_step ln n_eff
  int num_blocks = 0;
};

/// Binary segmentation of x (any mean) with k chosen by the modified BIC (header comment).
LevelsSegmentation SegmentLevels(const Eigen::VectorXd& x, double sample_rate_hz,
                                 const LevelsOptions& options);

/// The noise model's lambda for the segmentation: tau AVAR(tau) at batch_s over the same at
/// block_s (1 for white noise; larger for every correlated term), at least 1. `allan_variance` is
/// the model's Allan variance as a function of tau (s).
template <typename AllanVariance>
double LevelsVarianceRatio(const AllanVariance& allan_variance, double block_s, double batch_s) {
  const double ratio = batch_s * allan_variance(batch_s) / (block_s * allan_variance(block_s));
  return ratio > 1.0 ? ratio : 1.0;
}

/// How the fitted levels read as random telegraph switching.
struct LevelsReading {
  int num_levels = 0;                ///< 2 when telegraph-like, else the number of segments
  bool telegraph_like = false;       ///< two alternating levels
  double mean_dwell_s = 0;           ///< record / number of segments
  double gm_correlation_time_s = 0;  ///< equivalent Gauss-Markov Tc = dwell / 2
  double half_separation_rad_s = 0;  ///< equivalent Gauss-Markov sigma (two-level only)
  std::string text;                  ///< one sentence
};

/// `levels` are the segment means (k + 1, in time order) with standard errors `levels_se`.
LevelsReading DescribeLevels(const std::vector<double>& levels,
                             const std::vector<double>& levels_se, double record_s);

}  // namespace fogpipe::model
