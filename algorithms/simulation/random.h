// Seeded, reproducible random numbers for the simulator.
//
// std::normal_distribution is implementation-defined (libstdc++, libc++ and MSVC give different
// sequences for the same engine), so fogpipe draws its own normals: std::mt19937_64 (its output
// sequence is fixed by the C++ standard, [rand.predef]) feeds Marsaglia's polar method
// (Marsaglia & Bray 1964). The only libm calls are sqrt (correctly rounded by IEEE 754) and log, so
// the same seed gives the same numbers on every platform whose log is correctly rounded (glibc),
// and the same numbers run after run on any one platform.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>

namespace fogpipe::simulation {

/// Derives an independent seed for one random stream (a noise term, an axis, a file) from the
/// user's seed, with SplitMix64 (Steele, Lea & Flood 2014) applied twice. Streams keep terms
/// independent of each other: adding a term to a simulation does not change the realisation of
/// the others.
std::uint64_t DeriveSeed(std::uint64_t seed, std::uint64_t stream);

/// Standard normal and uniform numbers from one seeded std::mt19937_64.
class RandomSource {
 public:
  explicit RandomSource(std::uint64_t seed);

  /// Uniform on [0, 1) with 53 random bits.
  double Uniform();
  /// Uniform on [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  /// Standard normal N(0, 1) by Marsaglia's polar method.
  double Normal();
  /// n independent N(0, 1) samples.
  Eigen::VectorXd Normals(Eigen::Index n);

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace fogpipe::simulation
