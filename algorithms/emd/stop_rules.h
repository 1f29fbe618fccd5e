// When to stop sifting one IMF.
//
// Every rule is evaluated after each sift k >= 1 on h_k (the signal after k envelope-mean
// subtractions) and on the statistics of that last sift (the envelopes of h_{k-1}):
//   - kFixedSifts: exactly `fixed_sifts` sifts (default 10). Wu & Huang (2004, 2009) use a fixed
//     count of about 10 because it makes EMD a fixed, dyadic filter bank on white noise and keeps
//     the result independent of the record length.
//   - kCauchy: Huang et al. (1998, eq. 5.5) stop when the "standard deviation" between two
//     consecutive sifts falls below 0.2-0.3. We use the ratio-of-sums form of Huang et al. (2003,
//     "A confidence limit for the EMD", Proc. R. Soc. A 459) SD_k = sum (h_{k-1} - h_k)^2 / sum
//     h_{k-1}^2 = sum m^2 / sum h_{k-1}^2, because the 1998 per-sample ratio divides by
//     h_{k-1}(t)^2 and diverges at every zero crossing.
//   - kSNumber: Huang et al. (2003): stop once the numbers of extrema and zero crossings differ by
//   at
//     most one and have stayed the same for S consecutive sifts.
//   - kRilling: Rilling, Flandrin & Goncalves (2003), with sigma(t) = |m(t)| / a(t) (mean over
//     half-range of the envelopes): stop when sigma < theta1 on all but a fraction alpha of the
//     samples, sigma < theta2 everywhere, and extrema and zero crossings differ by at most one (as
//     in their emd.m). Difference from emd.m: emd.m tests the envelopes of h_{k-1} and then keeps
//     h_{k-1}; our pass has already subtracted that mean when the test is made, so we keep h_k,
//     which is one subtraction closer to a zero mean, and check the counts on h_k.
//   - Any rule: the sift cap `max_sifts` (kSiftCap), and a signal that has lost its extrema
//     (fewer than 2 maxima or 2 minima: kTooFewExtrema) stop the sifting.
//
// Why a fixed count is the default: the adaptive rules do not define the same filter for every
// record length. Huang 1998's SD is a sum over samples, so it grows with N; even normalized (as
// here) SD and Rilling's fractions are averages, in which a local defect weighs 1/N. And S-number
// and Rilling (through its count condition) ask that the extrema and zero crossings of the WHOLE
// record agree, or stay unchanged for S sifts; on a long record some extremum appears or vanishes
// somewhere in almost every sift, so they run to the cap (sift counts measured on white noise:
// docs/method.md, "Step 1"). A fixed count gives the same filter bank for any N (Wu & Huang 2004:
// ratio 2), costs a known time, and is what tests/algorithms/emd/emd_test.cpp checks against the
// dyadic law.
#pragma once

#include <string>

#include "algorithms/emd/envelope.h"
#include "algorithms/emd/extrema.h"

namespace fogpipe::emd {

/// The sifting stop rule (see the file comment).
enum class StopRule { kFixedSifts, kCauchy, kSNumber, kRilling };

/// Why the sifting of one IMF stopped.
enum class SiftStop {
  kFixedCount,     ///< kFixedSifts: the fixed count was reached.
  kThresholdMet,   ///< kCauchy: SD below cauchy_sd.
  kSNumberMet,     ///< kSNumber: counts stable for S sifts.
  kRillingMet,     ///< kRilling: the three thresholds met.
  kSiftCap,        ///< max_sifts reached before the rule was met.
  kTooFewExtrema,  ///< The sifted signal has fewer than 2 maxima or 2 minima.
};

/// "fixed_sifts", "cauchy", "s_number", "rilling".
const char* ToString(StopRule rule);
/// "fixed_count", "threshold_met", "s_number_met", "rilling_met", "sift_cap", "too_few_extrema".
const char* ToString(SiftStop stop);

/// Parameters of the stop rules, with their defaults. EmdOptions derives from this struct, so
/// they are set as options.stop_rule, options.fixed_sifts, ...
struct StopCriteria {
  /// Sifting stop rule. Default: a fixed number of sifts, the choice that makes EMD a dyadic filter
  /// bank on noise independently of the record length (see the file comment).
  StopRule stop_rule = StopRule::kFixedSifts;
  /// kFixedSifts: sifts per IMF (Wu & Huang 2004 use 10).
  int fixed_sifts = 10;
  /// kCauchy: stop when sum m^2 / sum h_{k-1}^2 <= cauchy_sd (Huang 1998: 0.2 to 0.3).
  double cauchy_sd = 0.2;
  /// kSNumber: consecutive sifts with unchanged counts (Huang et al. 2003 suggest 3 to 5).
  int s_number = 4;
  /// kRilling: theta1, theta2, alpha of Rilling, Flandrin & Goncalves (2003).
  double rilling_theta1 = 0.05;
  double rilling_theta2 = 0.5;
  double rilling_alpha = 0.05;
  /// Cap on sifts per IMF for every rule (an IMF that hits it is flagged kSiftCap, and the
  /// decomposition kNoConvergence). For kFixedSifts it must be >= fixed_sifts.
  int max_sifts = 100;
};

/// The statistics the fused sift pass must gather for `rule`.
SiftStatisticsKind StatisticsFor(StopRule rule);

/// Decides, sift after sift, when one IMF is done. One object per IMF.
class SiftStopper {
 public:
  /// `initial` are the counts of h_0, the signal the IMF is sifted from (S-number compares
  /// every sift's counts with the previous ones).
  SiftStopper(const StopCriteria& criteria, const ExtremaCounts& initial)
      : criteria_(criteria),
        previous_extrema_(initial.num_extrema()),
        previous_zero_crossings_(initial.num_zero_crossings) {}

  /// Called after sift `sifts` (>= 1) with the counts of h_k and the statistics of that sift.
  /// Returns true and sets *reason when the sifting must stop.
  bool ShouldStop(int sifts, const ExtremaCounts& counts, const SiftStatistics& stats, int n,
                  SiftStop* reason);

  /// True when no sift is needed after `sifts` sifts other than to produce counts, i.e. the rule
  /// will stop at this count whatever the counts are (fixed count or cap). Lets the caller skip
  /// storing knots.
  bool StopsAt(int sifts) const;

 private:
  StopCriteria criteria_;
  int previous_extrema_;
  int previous_zero_crossings_;
  int stable_sifts_ = 0;
};

}  // namespace fogpipe::emd
