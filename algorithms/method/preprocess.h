// Preprocessing before EMD, as the paper did it (Liu, Liu & Shen 2018, section 2; docs/method.md,
// "The paper's data and preprocessing"): the start-up transient is dropped, gross errors (outliers)
// are replaced, the mean is removed, and windowed mean and variance are computed for the
// stationarity check (their Fig. 2). Missing samples (NaN) are bridged by the recording reader
// (pipeline/io/missing_samples.h) before this step; here a non-finite sample is an error.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "algorithms/common/for_each.h"
#include "algorithms/common/status.h"

namespace fogpipe::method {

struct PreprocessOptions {
  /// Seconds dropped at the start (the output is biased right after switch-on). Default 0.
  double drop_start_s = 0.0;
  /// Outliers: a Hampel identifier (Hampel 1974; Pearson 2002) with a pooled scale. With m_k the
  /// median of the 2 h + 1 samples centred on k (h = hampel_half_window; windows shrink at the
  /// ends) and e_k = x_k - m_k, sample k is an outlier when
  ///   |e_k| > hampel_threshold * 1.4826 * median(|e_j|, j in k's block of hampel_scale_block),
  /// and is replaced by m_k. 1.4826 makes the MAD a consistent estimate of the standard deviation
  /// of Gaussian noise, so k = 5 flags what is 5 sigma off the local level (probability 5.7e-7 per
  /// Gaussian sample). The scale is pooled over blocks (default 1000 samples, relative standard
  /// error ~4 %) rather than taken over the 11-sample window itself: an 11-sample MAD is so noisy
  /// that it flagged 119 of 20000 pure Gaussian samples when we tried it, while blocks still
  /// follow slow changes of the noise level.
  bool remove_outliers = true;
  int hampel_half_window = 5;
  double hampel_threshold = 5.0;
  int hampel_scale_block = 1000;
  /// Length of the non-overlapping windows of the stationarity check, seconds. <= 0: one
  /// twentieth of the (kept) record.
  double window_s = 0.0;
  /// Fewest samples kept after the drop. EMD and an AR(20) fit need a few hundred. Default 64.
  int min_samples = 64;
  /// When set, the local medians and the blocks' scales are found in parts of at least 65536
  /// samples through it. Each median is a value of its window, however it is found, so the
  /// output does not depend on the parts (a zero median may differ in its sign, see LocalMediansOf
  /// in preprocess.cpp).
  ForEach for_each;

  bool IsValid(std::string* error) const;
};

struct PreprocessSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  long long dropped_samples = 0;  ///< At the start (drop_start_s).
  long long outliers = 0;         ///< Samples replaced by the local median.
};

struct Preprocessed {
  /// The kept signal, outliers replaced, mean removed; units of the input.
  Eigen::VectorXd signal;
  /// The mean removed from `signal`, units of the input.
  double mean_removed = 0.0;
  /// Indices (into the input, before the drop) of the samples replaced as outliers.
  std::vector<long long> outlier_indices;
  /// Stationarity check: length of one window in samples, and per window the mean and the
  /// (population) variance of the kept signal before the mean was removed.
  long long window_samples = 0;
  Eigen::VectorXd window_mean;
  Eigen::VectorXd window_variance;
  /// A short text of the outlier rule, stored with the indices (e.g. "hampel h=5 k=5 ...").
  std::string outlier_rule;
  PreprocessSummary summary;
};

/// What the raw signal's Allan table and noise terms rest on, one sentence for every place that
/// shows them (Table 5 of `run` and `info`, the results file's allan/raw): `run` analyses the
/// preprocessed signal, `fogpipe allan` the recording as stored, so their terms for the same file
/// differ by exactly this preprocessing (the Allan code path is the same).
std::string PreprocessingNote(long long dropped_samples, long long outliers);

/// Preprocesses one axis `x` sampled at `sample_rate_hz`. A constant signal (zero variance after
/// the steps above) is kNumericalFailure: no noise to analyse.
Preprocessed Preprocess(const Eigen::VectorXd& x, double sample_rate_hz,
                        const PreprocessOptions& options);

}  // namespace fogpipe::method
