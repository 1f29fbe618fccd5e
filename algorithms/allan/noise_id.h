// Power-law noise identification at one averaging factor, for choosing the EDF of a variance
// estimate (NIST SP 1065 section 5.6; the same two-method scheme as Stable32).
//
//  - At least 30 averages: the lag-1 autocorrelation method of Riley & Greenhall, "Power law noise
//    identification using the lag 1 autocorrelation", EFTF 2004: the m-averaged frequency series is
//    differenced d times until rho = r1 / (1 + r1) < 0.25 (or d = dmax), then
//    alpha = -2 (rho + d), rounded.
//  - Fewer: the B1 bias ratio (Barnes 1969; Howe, Beard, Greenhall & Riley, PTTI 2000), the
//    N-sample variance of the N = n / m averages over the overlapping Allan variance at m, compared
//    with its expectation for each type (boundaries at geometric means), separates alpha = 0, -1,
//    -2 (and -3 for the Hadamard variance) from phase noise; phase noise is split into white
//    (alpha = 2) and flicker (alpha = 1) by R(n) = Mod AVAR / AVAR (NIST TN 1337, A-6).
//    (IdentifyNoise is this textbook scheme at one tau.)
//
// Along the tau grid (IdentifyNoiseTypes) two rules combine these per-tau methods:
//
//  - kCalibrated (default), chosen by the coverage of the resulting confidence intervals on
//    simulated power-law noise (docs/allan-statistics.md). The lag-1 method misreads white FM as
//    flicker PM in a few per cent of records at 30-100 averages (the rounding margin of rho is
//    +-0.25 against a standard error ~1/sqrt(averages)), and flicker PM's EDF is ten times white
//    FM's there, so each such row prints an interval three times too narrow. R(n) separates phase
//    from frequency noise far more sharply (0.5 for white FM against 0.1-0.2 for flicker PM and
//    1/m for white PM, from all n samples rather than n / m averages), so it confirms every phase-
//    noise reading from m = 8 (frequency noise only below 1000 averages). It also splits white
//    from flicker PM, where the lag-1 statistic of m-averaged flicker PM drifts towards white PM's
//    as m grows (a third to a half of flicker-PM rows read as white PM at m = 16-512 of 2^14
//    samples, intervals then covering 36-64 %); with 8-29 averages B1 reads random-walk FM alone
//    and otherwise R(n) separates phase from frequency noise and B1 orders the frequency noises.
//    Below 8 averages no statistic separates the types (B1's classes overlap at 4-7 averages), and
//    phase noise cannot follow frequency noise at a longer tau in a sum of power laws (Allan
//    variances fall as tau^-(alpha + 1) for frequency noise and tau^-2 (times ln tau for flicker)
//    for phase noise, so the dominant alpha is non-increasing in tau): both cases keep the type of
//    the shorter tau.
//  - kStable32 reproduces Stable32's Alpha column on every row of its PHASE.DAT, OCXO and
//    flicker-FM reports: lag-1 from 30 averages; below, B1 against Howe et al.'s expectations
//    evaluated at the deviation's count of differences (Stable32's "#") with the non-overlapping
//    two-sample variance, R(n) for the phase-noise split; with fewer than 9 averages or 9
//    differences, the type of the shorter tau.
//
// The lag-1 method is one streaming pass over the m-averages computing the sums of all difference
// orders at once (no copies), so identification at m = 1 of 1e7 samples costs one read of them.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

namespace fogpipe::allan {

enum class NoiseIdMethod {
  kLag1Autocorrelation,  ///< "lag1": Riley & Greenhall's lag-1 autocorrelation.
  kLag1AndRn,            ///< "lag1_rn": lag-1 read phase noise, R(n) chose another type.
  kB1Ratio,              ///< "b1": the B1 bias ratio.
  kB1AndRn,              ///< "b1_rn": B1 for frequency noise types, R(n) for phase noise.
  kCarried,              ///< "carried": the type of the shorter tau (see the rules above).
  kNone,                 ///< "none": fewer than 4 averages and no shorter tau.
};

/// Stable name of a method ("lag1", "lag1_rn", "b1", "b1_rn", "carried", "none"), as stored in
/// results files and printed in tables.
const char* ToString(NoiseIdMethod method);
/// ToString of each method, for string columns.
std::vector<std::string> MethodNames(const std::vector<NoiseIdMethod>& methods);

enum class NoiseIdRule {
  kCalibrated,  ///< Chosen by measured interval coverage (see above); the default.
  kStable32,    ///< Reproduces Stable32's Alpha column.
};

const char* ToString(NoiseIdRule rule);  ///< "calibrated", "stable32"
/// Parses ToString's names; false for anything else.
bool ParseNoiseIdRule(const std::string& name, NoiseIdRule* rule);

struct NoiseId {
  /// Power-law exponent of S_y(f) ~ f^alpha of the rate: 2 white PM (quantization), 1 flicker
  /// PM, 0 white FM (angle random walk), -1 flicker FM (bias instability), -2 random walk FM (rate
  /// random walk), -3, -4 (Hadamard only). Clamped to alpha >= 2 - 2 d.
  int alpha = 0;
  /// Unrounded estimate (lag-1 method only; NaN otherwise).
  double alpha_estimate = 0.0;
  NoiseIdMethod method = NoiseIdMethod::kNone;
};

/// Identifies the dominant noise at averaging factor m from `phase` (MeanRemovedPhase of the rate
/// samples, n + 1 points). d = 2 for Allan variances, 3 for Hadamard. Returns method kNone (and
/// alpha 0) when fewer than 4 averages exist.
///
/// `allan_variance_m` is the Allan variance at m in (phase units / m)^2, i.e. as returned by
/// DeviationVariances, for the B1 ratio's denominator; pass the overlapping one when the caller
/// has it. NaN (default) means: use the two-sample variance of the N averages themselves (Barnes'
/// textbook B1). Either way the cost is O(n / m) unless the R(n) step runs (phase noise at < 30
/// averages), which is O(n).
NoiseId IdentifyNoise(const Eigen::VectorXd& phase, long long m, int d,
                      double allan_variance_m = std::numeric_limits<double>::quiet_NaN());

/// R(n) = Mod AVAR(m) / AVAR(m), both overlapping, from the phase (NIST TN 1337, A-6): about 1/m
/// for white PM, 3.37 / (1.04 + 3 ln(pi m)) for flicker PM, 0.5 / 0.67 / 0.82 for white /
/// flicker / random-walk FM. O(n). NaN when n < 3 m. `allan_variance_m` > 0: the overlapping
/// Allan variance at m as DeviationVariances returns it, when the caller has it (saves a pass).
double ModifiedToAllanRatio(const Eigen::VectorXd& phase, long long m,
                            double allan_variance_m = std::numeric_limits<double>::quiet_NaN());

/// ModifiedToAllanRatio at each factor of `m` (increasing; `allan_variance_m[k]` as its argument
/// for m[k]), bit for bit: four factors side by side in each pass over the phase (one factor's
/// additions form a chain that has to stay in order, about 4 cycles a window; four such chains
/// share the vector units), the passes shared among `threads` threads.
std::vector<double> ModifiedToAllanRatios(const Eigen::VectorXd& phase,
                                          const std::vector<long long>& m,
                                          const std::vector<double>& allan_variance_m,
                                          int threads = 1);

/// Noise types along a grid of averaging factors `m` (increasing) by `rule`. `count[k]` is the
/// deviation's number of difference terms at m[k] (Stable32's "#"); `overlapping_avar[k]` the
/// overlapping Allan variance at m[k] in (phase units / m)^2, NaN where not computed (kCalibrated
/// uses it for B1 below 30 averages). d as for IdentifyNoise. `threads` share the lag-1 readings
/// and the R(n) passes; the result does not depend on it.
std::vector<NoiseId> IdentifyNoiseTypes(const Eigen::VectorXd& phase,
                                        const std::vector<long long>& m,
                                        const std::vector<long long>& count,
                                        const std::vector<double>& overlapping_avar, int d,
                                        NoiseIdRule rule, int threads = 1);

}  // namespace fogpipe::allan
