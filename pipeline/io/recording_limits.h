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

/// Sample magnitudes (in the file's own unit) outside [1e-60, 1e60], zero aside, are refused.
/// The Kalman filters' Riccati equations multiply two variances (a sample's fourth power), and
/// sums over up to 1e10 samples add ten orders: x^4 * 1e10 stays below the largest double
/// (1.8e308) for |x| < 1e74, and (1e-60)^4 = 1e-240 stays a normal double (not subnormal,
/// ~1e-308, where precision is lost and the EMD's extrema search degenerates). The margin of 14
/// orders covers the unit conversion (deg/h to rad/s is 5e-6) and the noise rules' scale factors.
/// Samples at 1e90, inside a looser bound, made the Riccati solver fail without naming the cause.
inline constexpr double kMaxMagnitude = 1e60;
inline constexpr double kMinMagnitude = 1e-60;

}  // namespace fogpipe::io::limits
