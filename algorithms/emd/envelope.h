// One sift: subtract the mean of the upper and lower envelopes from the signal, in one pass.
#pragma once

#include <cstdint>

#include "algorithms/common/for_each.h"
#include "algorithms/emd/extrema.h"

namespace fogpipe::emd {

/// What the stop rule needs to know about a sift, gathered in the same pass.
enum class SiftStatisticsKind {
  kNone,     ///< Fixed sift count, S-number: nothing beyond the extrema counts.
  kCauchy,   ///< Sum of squares of the mean and of the signal before the sift.
  kRilling,  ///< Counts of samples where |mean| exceeds theta * amplitude.
};

/// Statistics of one sift h_k = h_{k-1} - m, with m = (U + L) / 2 and a = |U - L| / 2 the mean and
/// half-range of the upper and lower envelopes of h_{k-1}.
struct SiftStatistics {
  double sum_mean_sq = 0.0;     ///< sum of m^2 (kCauchy).
  double sum_input_sq = 0.0;    ///< sum of h_{k-1}^2 (kCauchy).
  int64_t num_over_theta1 = 0;  ///< samples with |m| > theta1 * a (kRilling).
  int64_t num_over_theta2 = 0;  ///< samples with |m| > theta2 * a (kRilling).
};

/// Replaces h[i] by h[i] - (U(i) + L(i)) / 2 for i = 0..n-1, where U and L are the splines through
/// `upper` and `lower` (moments already solved, knots read from h itself, see extrema.h). One
/// fused pass: both splines are walked with a moving interval index (no search), each piece is
/// converted to a polynomial once, when the walk enters it, and before any sample it covers is
/// overwritten; outside the knots the end pieces are extended.
SiftStatistics SubtractEnvelopeMean(double* h, int n, const EnvelopeKnots& upper,
                                    const EnvelopeKnots& lower, SiftStatisticsKind kind,
                                    double theta1 = 0.0, double theta2 = 0.0);

/// The same pass over `parts` contiguous ranges of samples, run through `for_each`. h is
/// bit-identical to SubtractEnvelopeMean's whatever the parts and the schedule: every sample is
/// computed from the same piece by the same arithmetic. Because a part overwrites its samples,
/// which may be knots of the pieces where a neighbouring part starts or ends, those boundary
/// pieces are converted to polynomials before any part starts. kCauchy runs the serial pass
/// (SubtractEnvelopeMean) instead: its sums, added part by part, would round differently; the
/// kRilling counts are exact integers and add up the same.
SiftStatistics SubtractEnvelopeMeanInParts(double* h, int n, const EnvelopeKnots& upper,
                                           const EnvelopeKnots& lower, SiftStatisticsKind kind,
                                           double theta1, double theta2, int parts,
                                           const ForEach& for_each);

}  // namespace fogpipe::emd
