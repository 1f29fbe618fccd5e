// a * b + c with one rounding where the CPU has a fused multiply-add (internal to
// algorithms/kalman).
//
// With FMA enabled (FOGPIPE_NATIVE builds on such CPUs) the compiler contracts a * b + c into a
// fused operation wherever it sees fit (GCC's default -ffp-contract=fast), and that choice depends
// on how the surrounding code was unrolled or vectorized: two loops computing the same expressions
// can round differently. Code that must give the same bits as another piece of code (the fused
// covariance step and PredictCovariance / JosephUpdate, tested) spells every multiply-add with
// MulAdd, leaving the compiler nothing to contract. Without FMA it is the plain expression (no
// contraction is possible, and std::fma would be a slow software routine).
#pragma once

#include <cmath>

namespace fogpipe::kalman::internal {

inline double MulAdd(double a, double b, double c) {
#ifdef __FMA__
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

}  // namespace fogpipe::kalman::internal
