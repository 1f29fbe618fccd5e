// Four doubles side by side in one vector value, for the kernels that run four independent
// recursions or sums at once (GCC/Clang vector extension: one AVX2 register, two SSE registers
// without AVX).
//
// Arithmetic on it is element-wise IEEE, so each element computes exactly what the same scalar
// code computes, whatever the other elements hold. The side-by-side kernels' bit-identity with
// their scalar twins rests on this, together with the contraction rules of kalman/mul_add.h.
#pragma once

#include <array>
#include <cstring>

namespace fogpipe {

typedef double Lanes4 __attribute__((vector_size(4 * sizeof(double))));

// __builtin_shufflevector: Clang, GCC from 12.
#if defined(__has_builtin)
#if __has_builtin(__builtin_shufflevector)
#define FOGPIPE_LANES_SHUFFLEVECTOR 1
#endif
#endif

/// Four consecutive doubles from p (any alignment).
inline Lanes4 LoadLanes4(const double* p) {
  Lanes4 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

/// The four elements of v to p, p + 1, p + 2, p + 3 (any alignment).
inline void StoreLanes4(double* p, Lanes4 v) { std::memcpy(p, &v, sizeof(v)); }

/// The 4 x 4 block row[k][j + u] (k, u < 4) by columns: element k of column u is row[k][j + u], for
/// four recursions side by side that each read their own series. Pairs of rows' halves are loaded
/// into one vector and interleaved within its 128-bit halves, the cheapest transpose where a vector
/// holds two 128-bit halves (AVX): no shuffle crosses the halves.
inline std::array<Lanes4, 4> LoadColumns4(const double* const row[4], long long j) {
#ifdef FOGPIPE_LANES_SHUFFLEVECTOR
  typedef double Lanes2 __attribute__((vector_size(2 * sizeof(double))));
  const auto halves = [&](int k0, int k1, long long i) {  // row[k0][i, i + 2), row[k1][i, i + 2)
    Lanes2 a, b;
    std::memcpy(&a, row[k0] + i, sizeof(a));
    std::memcpy(&b, row[k1] + i, sizeof(b));
    return __builtin_shufflevector(a, b, 0, 1, 2, 3);
  };
  const Lanes4 t0 = halves(0, 2, j), t1 = halves(1, 3, j);
  const Lanes4 t2 = halves(0, 2, j + 2), t3 = halves(1, 3, j + 2);
  return {__builtin_shufflevector(t0, t1, 0, 4, 2, 6), __builtin_shufflevector(t0, t1, 1, 5, 3, 7),
          __builtin_shufflevector(t2, t3, 0, 4, 2, 6), __builtin_shufflevector(t2, t3, 1, 5, 3, 7)};
#else
  std::array<Lanes4, 4> column;
  for (int u = 0; u < 4; ++u)
    column[u] = Lanes4{row[0][j + u], row[1][j + u], row[2][j + u], row[3][j + u]};
  return column;
#endif
}

}  // namespace fogpipe
