// The results file layout, fogpipe-results-v2 (schemas/results-v2.json, schemas/results-v2.md):
// names shared by the writer, the readers and the tests.
#pragma once

namespace fogpipe::io::results {

/// Root attribute `fogpipe_format`.
inline constexpr const char* kFormat = "fogpipe-results-v2";
/// The previous layout (one scalar dataset per noise-term number, float64 IMFs by default), which
/// this version no longer reads: `fogpipe run` rewrites such files.
inline constexpr const char* kPreviousFormat = "fogpipe-results-v1";
/// allan/<signal>/noise/<kNoiseTable>: the noise terms, one row per term (WriteNoiseTable).
inline constexpr const char* kNoiseTable = "terms";
/// allan/<signal>/<kAllanTable>: the Allan table, one row per tau.
inline constexpr const char* kAllanTable = "table";
/// Attribute of a table whose columns each have one unit: the units, one per field in field
/// order ("" for a text field).
inline constexpr const char* kFieldUnitsAttribute = "field_units";
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
