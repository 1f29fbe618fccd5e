// Four doubles side by side in one vector value, for the kernels that run four independent
// recursions or sums at once (GCC/Clang vector extension: one AVX2 register, two SSE registers
// without AVX), and the one fused operation a kernel may ask for, MulAdd.
//
// Why a lane computes its scalar twin's bits (kernels.h): arithmetic on Lanes4 is element-wise
// IEEE, so each element computes exactly what the same scalar expression computes, whatever the
// other elements hold, provided both are the same expression rounded the same way. The build
// never contracts a * b + c into a fused multiply-add on its own (-ffp-contract=off for every
// target, fogpipe::build_settings in the top CMakeLists.txt): GCC's default contracts where its
// optimizer sees fit, and that depends on how a loop was unrolled or vectorized, so two loops
// computing the same expression could round differently (measured: the same expression fused in
// one loop and not in another). A kernel that wants the fused operation (the latency of its
// dependency chain) says so with MulAdd, in its scalar and lane variants alike.
#pragma once

#include <array>
#include <cmath>
#include <cstring>
#ifdef __FMA__
#include <immintrin.h>
#endif

namespace fogpipe::kernels {

typedef double Lanes4 __attribute__((vector_size(4 * sizeof(double))));

// FOGPIPE_LANE_KERNEL, before a function whose loop runs on Lanes4: in the portable build on
// x86-64 with glibc the function is compiled twice, for the x86-64 baseline and for AVX2, and the
// loader picks the AVX2 one on CPUs that have it (GCC/Clang target_clones, an ifunc resolved
// once). Why: without AVX a Lanes4 is two SSE registers, and GCC passes its shuffles, element
// inserts and spills through the stack, where each reload waits on a failed store forwarding (the
// modified Allan windows ran 4 times slower than with AVX2, docs/performance.md). The same bits
// either way: "avx2" does not enable FMA and the build never contracts (-ffp-contract=off), so
// each element-wise operation rounds as in the baseline; the preprocessor still sees the
// baseline, so Eigen keeps its SSE2 code and the order of its reductions.
// Two rules for such a function: every function it passes Lanes4 values to is inline (the AVX2
// clone passes them in one register, the baseline in memory), and Lanes4 values it reads from
// memory that it did not allocate on its own stack are 32-byte aligned (the baseline aligns the
// type to 16 bytes only, and std::allocator follows the baseline; fixed_order::Buffer aligns).
#if defined(__x86_64__) && defined(__GLIBC__) && !defined(__AVX2__) && \
    (defined(__GNUC__) || defined(__clang__))
#define FOGPIPE_LANE_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define FOGPIPE_LANE_KERNEL
#endif

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

/// a * b + c with one rounding where the CPU has a fused multiply-add (FOGPIPE_NATIVE builds on
/// such CPUs); without FMA the plain expression (std::fma would be a slow software routine).
inline double MulAdd(double a, double b, double c) {
#ifdef __FMA__
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

/// MulAdd of each element: one fused multiply-add per element where the scalar MulAdd fuses.
inline Lanes4 MulAdd(Lanes4 a, Lanes4 b, Lanes4 c) {
#ifdef __FMA__
  return Lanes4(_mm256_fmadd_pd(__m256d(a), __m256d(b), __m256d(c)));
#else
  return a * b + c;
#endif
}

/// v in every element (for T = double, v itself): the scalar operand of a kernel templated on T.
template <typename T>
T Splat(double v);
template <>
inline double Splat<double>(double v) {
  return v;
}
template <>
inline Lanes4 Splat<Lanes4>(double v) {
  return Lanes4{v, v, v, v};
}

}  // namespace fogpipe::kernels
