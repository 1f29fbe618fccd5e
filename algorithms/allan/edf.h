// Equivalent degrees of freedom of Allan and Hadamard variance estimates for power-law noise,
// by the algorithm of Greenhall & Riley, "Uncertainty of stability variances based on finite
// differences", 35th PTTI (2003) (also used by Stable32 and NIST SP 1065, section 5.3). Only the
// unmodified variances (filter factor F = m) are covered: ADEV, OADEV, HDEV, OHDEV.
#pragma once

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

}  // namespace fogpipe::allan
