// What the recording reader accepts beyond the letter of contract v1: bounds that keep a damaged
// or hostile file from steering fogpipe into unbounded memory, time or meaningless numbers. Each
// bound is checked once, by the reader (recording_reader.cpp), before any sample is allocated.
#pragma once

#include <cstdint>

namespace fogpipe::io::limits {

/// Axes per recording. A gyro or IMU has 1..6; 4096 leaves room for arrays of sensors while a
/// [N, A] dataset with more columns than that is a transposed matrix or a damaged header.
inline constexpr long long kMaxAxes = 4096;

/// Samples per axis: 2^36 (a year at 2 kHz). Beyond it the per-axis analysis alone would need
/// terabytes (graph/memory_budget.h).
inline constexpr long long kMaxSamples = 1ll << 36;

/// Largest ratio of declared (uncompressed) bytes to the file's size. zlib's deflate never
/// compresses better than 1032:1 (RFC 1951: at most 258 bytes per 2-bit code pair, zlib's
/// technical notes, "maximum compression factor"); shuffle adds nothing to that bound. A file
/// declaring more is damaged or declares data it never wrote.
inline constexpr double kMaxExpansion = 1032.0;

/// Sample rates outside [1e-6 Hz, 1e9 Hz] (one sample per 11.6 days .. 1 GHz) are refused: every
/// tau of an Allan table is m / rate, and a rate like 5e-324 Hz makes them all infinite.
inline constexpr double kMinSampleRateHz = 1e-6;
inline constexpr double kMaxSampleRateHz = 1e9;

/// Sample magnitudes (in the file's own unit) outside [1e-100, 1e100], zero aside, are refused:
/// the analysis squares and sums samples (variances, Allan, AR recursions); 1e100^2 and
/// (1e-100)^2 are still normal doubles, while 1e300 overflows and subnormal values (~1e-310)
/// lose all precision and make the EMD's extrema search degenerate.
inline constexpr double kMaxMagnitude = 1e100;
inline constexpr double kMinMagnitude = 1e-100;

}  // namespace fogpipe::io::limits
