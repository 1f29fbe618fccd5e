// Several bias levels (catalog term bias_levels): a piecewise-constant bias with k >= 2 jumps,
// and the levels test of the time view that shows such a bias where the Allan view cannot.
//
// Why. k jumps of the bias add to the Allan variance the law of a rate random walk (K^2 =
// sum D^2 / T; a single step: targeted_tests.h), and random telegraph switching (a bias jumping
// between two levels with exponential dwell times, Machlup 1954) has exactly the Lorentzian
// spectrum and Allan law of a first-order Gauss-Markov process of sigma a / 2 (a the level
// separation) and correlation time tau_d / 2 (tau_d the mean dwell). The second-order views
// (Allan, PSD) cannot tell them from those Gaussian terms, and the fitted K grows to absorb them;
// a segmentation of the residual into constant levels can.
//
//   Segmentation (SegmentLevels): the exact optimal partition of the residual's block means
//   (block_s) by PELT (Killick, Fearnhead & Eckley 2012), cost RSS / (sigma2 lambda) per segment
//   plus a penalty of penalty_per_step ln n_eff per step, n_eff = m / lambda (m blocks): the
//   modified BIC of Zhang & Siegmund (2007), 3 ln n per change point (a size, a time, and the
//   time searched over the record). sigma2 is the block means' short-run variance from their first
//   differences, robustly (median; jumps are a few outliers there). lambda, the long-run to
//   short-run variance ratio of the noise at the segments' scale, is either given (the levels test
//   passes the fitted noise model's, LevelsVarianceRatio) or estimated by batch means of
//   lambda_batch_s of the residual that the levels found so far leave, from lambda = 1 to a fixed
//   point (the fit of the term). Each step is then refined to the sample, within its block and the
//   neighbouring ones, by the exact two-segment least squares.
//
//   Levels or a random walk: k jumps are one realisation of what a rate random walk makes in
//   every block, and a true random walk is cut into as many levels as its wander allows. The
//   chosen steps stand only where they keep walk_penalty_per_step ln n_eff per step of -2 ln L
//   beside a random walk: the -2 ln L of the block means as a local-level model (Harvey 1989: a
//   random walk plus the white noise sigma2 lambda, the walk's variance fitted by maximum
//   likelihood) minus the same with the levels removed. Jumps that a random walk would have to be
//   rough everywhere to follow keep most of their gain; a random walk's staircase does not (the
//   walk fitted to the rest explains it). Otherwise no step is chosen. The penalty is below the
//   BIC of a time and a size (2 ln n_eff), as the walk fitted without the levels is rougher than
//   any walk in the record and takes part of their gain: 1.5 separates 3-5 steps at 3-5 times the
//   noise floor from the staircases of a random walk ruling the long taus (docs/compare.md).
//
//   Levels test (time view, views.h): the segmentation of the model's residual with lambda from
//   the fitted noise model without rate random walk and rate ramp (the levels inflate exactly
//   those); two or more steps fail the view with error = their -2 ln L drop over their penalty.
//   One step is left to the single-step tests (bias_step).
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
  /// Penalty per step beside a random walk, in units of ln n_eff (header comment).
  double walk_penalty_per_step = 1.5;
  /// Batch length of the residual's variance ratio lambda, s, and the most re-segmentations.
  double lambda_batch_s = 60.0;
  int lambda_iterations = 4;
  /// lambda given (> 0: the noise model's, LevelsVarianceRatio) instead of estimated from the data.
  double variance_ratio = 0.0;
  /// Shortest segment, s.
  double min_segment_s = 20.0;
  /// Most bytes a dense design of the steps may take (8 N per step; 0: no limit). The term's fit
  /// holds one column of N doubles per step, so a segmentation into more steps than this allows
  /// keeps none and reports their number (LevelsSegmentation::too_many_steps). 512 MiB: 310
  /// steps on 6 h at 10 Hz, 7 on 24 h at 100 Hz.
  double max_design_bytes = 512.0 * 1024 * 1024;
  bool IsValid(std::string* error) const;
};

/// The steps of a piecewise-constant fit: sample indices where the new level starts, ascending.
struct LevelsSegmentation {
  std::vector<long> step_index;
  double long_run_variance_ratio = 1.0;  ///< lambda of the block means' residual
  double short_run_variance = 0;         ///< of a block mean, (units of x)^2
  double gain = 0;     ///< -2 ln L drop of the steps (variance short_run_variance * lambda)
  double penalty = 0;  ///< per step: penalty_per_step ln n_eff
  /// -2 ln L drop of the chosen steps beside a random walk whose variance is fitted with and
  /// without them (header comment); 0 when PELT chose no step.
  double gain_beside_walk = 0;
  int num_blocks = 0;
  /// Steps found beyond LevelsOptions::max_design_bytes (then step_index is empty), else 0, and
  /// the most a dense fit of this record holds (max_design_bytes / 8 N) when they are.
  int too_many_steps = 0;
  long max_design_steps = 0;
};

/// The optimal segmentation of x (any mean) into levels, k chosen by the modified BIC and kept
/// only where the levels beat a random walk (header comment).
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
