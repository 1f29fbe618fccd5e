#include "algorithms/emd/stop_rules.h"

#include <cstdlib>

namespace fogpipe::emd {

const char* ToString(StopRule rule) {
  switch (rule) {
    case StopRule::kFixedSifts:
      return "fixed_sifts";
    case StopRule::kCauchy:
      return "cauchy";
    case StopRule::kSNumber:
      return "s_number";
    case StopRule::kRilling:
      return "rilling";
  }
  return "unknown";
}

const char* ToString(SiftStop stop) {
  switch (stop) {
    case SiftStop::kFixedCount:
      return "fixed_count";
    case SiftStop::kThresholdMet:
      return "threshold_met";
    case SiftStop::kSNumberMet:
      return "s_number_met";
    case SiftStop::kRillingMet:
      return "rilling_met";
    case SiftStop::kSiftCap:
      return "sift_cap";
    case SiftStop::kTooFewExtrema:
      return "too_few_extrema";
  }
  return "unknown";
}

SiftStatisticsKind StatisticsFor(StopRule rule) {
  switch (rule) {
    case StopRule::kCauchy:
      return SiftStatisticsKind::kCauchy;
    case StopRule::kRilling:
      return SiftStatisticsKind::kRilling;
    case StopRule::kFixedSifts:
    case StopRule::kSNumber:
      break;
  }
  return SiftStatisticsKind::kNone;
}

bool SiftStopper::StopsAt(int sifts) const {
  if (criteria_.stop_rule == StopRule::kFixedSifts && sifts >= criteria_.fixed_sifts) return true;
  return sifts >= criteria_.max_sifts;
}

bool SiftStopper::ShouldStop(int sifts, const ExtremaCounts& counts, const SiftStatistics& stats,
                             int n, SiftStop* reason) {
  const int extrema = counts.num_extrema();
  const int zero_crossings = counts.num_zero_crossings;
  const bool imf_counts = std::abs(extrema - zero_crossings) <= 1;
  bool met = false;
  SiftStop met_reason = SiftStop::kFixedCount;
  switch (criteria_.stop_rule) {
    case StopRule::kFixedSifts:
      met = sifts >= criteria_.fixed_sifts;
      met_reason = SiftStop::kFixedCount;
      break;
    case StopRule::kCauchy:
      // SD = sum m^2 / sum h_{k-1}^2; a zero input (sum 0) has nothing left to sift.
      met = stats.sum_mean_sq <= criteria_.cauchy_sd * stats.sum_input_sq;
      met_reason = SiftStop::kThresholdMet;
      break;
    case StopRule::kSNumber:
      if (imf_counts && extrema == previous_extrema_ &&
          zero_crossings == previous_zero_crossings_) {
        ++stable_sifts_;
      } else {
        stable_sifts_ = 0;
      }
      met = stable_sifts_ >= criteria_.s_number;
      met_reason = SiftStop::kSNumberMet;
      break;
    case StopRule::kRilling: {
      // mean(sigma > theta1) <= alpha and no sigma > theta2 (Rilling et al. 2003).
      const bool fraction_ok =
          static_cast<double>(stats.num_over_theta1) <= criteria_.rilling_alpha * n;
      met = fraction_ok && stats.num_over_theta2 == 0 && imf_counts;
      met_reason = SiftStop::kRillingMet;
      break;
    }
  }
  previous_extrema_ = extrema;
  previous_zero_crossings_ = zero_crossings;
  if (met) {
    *reason = met_reason;
    return true;
  }
  if (sifts >= criteria_.max_sifts) {
    *reason = SiftStop::kSiftCap;
    return true;
  }
  return false;
}

}  // namespace fogpipe::emd
