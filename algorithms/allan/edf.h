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
double GreenhallEdf(int alpha, int d, long long m, long long n_phase, bool overlapping);

}  // namespace fogpipe::allan
