// Four doubles side by side in one vector value, for the kernels that run four independent
// recursions or sums at once (GCC/Clang vector extension: one AVX2 register, two SSE registers
// without AVX).
//
// Arithmetic on it is element-wise IEEE, so each element computes exactly what the same scalar
// code computes, whatever the other elements hold. The side-by-side kernels' bit-identity with
// their scalar twins rests on this, together with the contraction rules of kalman/mul_add.h.
#pragma once

#include <cstring>

namespace fogpipe {

typedef double Lanes4 __attribute__((vector_size(4 * sizeof(double))));

/// Four consecutive doubles from p (any alignment).
inline Lanes4 LoadLanes4(const double* p) {
  Lanes4 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

/// The four elements of v to p, p + 1, p + 2, p + 3 (any alignment).
inline void StoreLanes4(double* p, Lanes4 v) { std::memcpy(p, &v, sizeof(v)); }

}  // namespace fogpipe
