// The results file layout, fogpipe-results-v1 (schemas/results-v1.json, schemas/results-v1.md):
// names shared by the writer, the reader and the tests.
#pragma once

namespace fogpipe::io::results {

/// Root attribute `fogpipe_format`.
inline constexpr const char* kFormat = "fogpipe-results-v1";
inline constexpr const char* kFormatAttribute = "fogpipe_format";
/// /provenance attribute holding the SHA-256 of the effective configuration (the rerun key).
inline constexpr const char* kConfigHashAttribute = "config_sha256";
/// Sign convention stored with every AR coefficient array.
inline constexpr const char* kSignConvention =
    "recursion: x(k) - mean = sum_i coefficients[i] (x(k-i) - mean) + e(k); MATLAB A(q) / the "
    "paper's Table 2 use a_i = -coefficients[i]";
/// Unit of every rate signal in a results file (SI inside; see algorithms/common/units.h).
inline constexpr const char* kRateUnits = "rad/s";
inline constexpr const char* kRateVarianceUnits = "(rad/s)^2";

}  // namespace fogpipe::io::results
