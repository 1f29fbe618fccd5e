// Equivalent degrees of freedom of Allan and Hadamard variance estimates for power-law noise,
// by the algorithm of Greenhall & Riley, "Uncertainty of stability variances based on finite
// differences", 35th PTTI (2003) (also used by Stable32 and NIST SP 1065, section 5.3):
// GreenhallEdf for the unmodified variances (filter factor F = m: ADEV, OADEV, HDEV, OHDEV),
// GreenhallModifiedEdf for the modified ones (F = 1: MDEV, TDEV). TotalVarianceEdf gives the
// total variance's EDF by NIST SP 1065's empirical formulas; DeviationEdf picks per kind.
#pragma once

#include "algorithms/allan/deviation.h"

namespace fogpipe::allan {

/// EDF of a d-th difference variance (d = 2 Allan, 3 Hadamard) at averaging factor m from
/// n_phase = N phase points (N = number of rate samples + 1), for power-law FM noise
/// S_y(f) ~ f^alpha, alpha in {2, 1, 0, -1, -2, -3, -4} with alpha + 2d > 1. overlapping selects
/// the stride S = m (overlapping) or S = 1. Returns NaN when the arguments are out of range or
/// no difference term exists.
///
/// Greenhall & Riley eq. (10) (the "basic sum", exact) is used whenever it has at most J_max = 100
/// terms, their Table 2 / Table 3 asymptotic forms for long records, and the large-m variant
/// (m' = infinity, or m' = J_max / r) where the paper prescribes it.
///
/// sampled_phase = false (default) reproduces Greenhall & Riley's case 2.1a for alpha <= 0 and
/// m (d + 1) <= J_max, which evaluates the kernel through the F = m filter; Stable32 does the same
/// (its Min/Max Sigma on PHASE.DAT imply EDF 782 at m = 1). For phase that is the running sum of
/// the rate samples (our case), the exact EDF of white FM at m = 1 is 2k^2 / (3k - 1) with k
/// = N - 2 terms (666 for N = 1001, confirmed by simulation), 17 % lower; at m = 2..33 Greenhall's
/// case 2.1a is 5-11 % high/low against simulation and NIST SP 1065's white-FM formula.
/// sampled_phase = true uses m' = infinity there as well (the case-2.1b kernel), which is exact
/// at m = 1 and within 1.5 % of SP 1065 for every m. Only alpha <= 0 is affected.
double GreenhallEdf(int alpha, int d, long long m, long long n_phase, bool overlapping,
                    bool sampled_phase = false);

/// EDF of the modified d-th difference variance (d = 2: Mod AVAR, hence also TDEV; d = 3: the
/// modified Hadamard variance) at averaging factor m from n_phase = N phase points, always
/// overlapping (stride S = m), for alpha in {2, ..., -4} with alpha + 2d > 1: Greenhall & Riley's
/// case 1 (filter factor F = 1, all alpha): the exact basic sum (eq. 10) when it has at most
/// J_max = 100 terms, their Table 1 asymptote (a0 - a1 / r) / r for r = M / S > d + 1, and the
/// m' = J_max / r variant otherwise. NaN when out of range or no term exists.
double GreenhallModifiedEdf(int alpha, int d, long long m, long long n_phase);

/// EDF of the total variance (TOTDEV) at factor m of n rate samples. NIST SP 1065 (Howe &
/// Greenhall's empirical fits, section 5.2.11 / Table 7): edf = b T / tau - c with T / tau
/// = n / m and (b, c) = (1.50, 0) white FM, (1.17, 0.22) flicker FM, (0.93, 0.36) random-walk FM.
/// SP 1065 gives no fit for phase noise; there, as Stable32 does (its bounds on the 53230A
/// counter's white-PM record imply exactly this), its simple AVAR formulas (SP 1065 Table 5) with
/// N = n + 1 phase points: white PM (N + 1)(N - 2m) / (2 (N - m)); flicker PM
/// exp(sqrt(ln((N - 1) / (2m)) ln((2m + 1)(N - 1) / 4))). NaN for alpha < -2 (TOTVAR is an Allan
/// variance: it cannot measure them) and for m beyond MaxAveragingFactor. Against simulation
/// (docs/allan-deviations.md) the fits hold for T / tau <= ~64 and overstate the EDF at shorter
/// tau (white FM at T / tau = 256: 384 against 286 simulated, about the OADEV value); the white-PM
/// formula overstates it at long tau. Both are kept because they are SP 1065's and Stable32's.
double TotalVarianceEdf(int alpha, long long m, long long n_rate_samples);

/// The EDF of `deviation` at factor m of n rate samples for noise type alpha: GreenhallEdf (with
/// `sampled_phase`), GreenhallModifiedEdf or TotalVarianceEdf.
double DeviationEdf(Deviation deviation, int alpha, long long m, long long n_rate_samples,
                    bool sampled_phase = false);

}  // namespace fogpipe::allan
