// Several of Eigen's sums over arrays of one length in one pass, each with the bits Eigen gives it
// alone.
//
// Eigen reduces a dynamic-size, linearly accessible expression (a dot product, a squared norm, the
// squared differences of the Allan sweep) in a fixed order (Eigen/src/Core/Redux.h, redux_impl
// for LinearVectorizedTraversal without unrolling): two packet accumulators over pairs of packets
// from the start, then their sum, then one more packet if a whole one is left, then the packet's
// horizontal sum (predux), then the last elements one by one; fewer elements than one packet are
// added one by one from the first. An expression without direct access (a product of elements)
// starts at element 0, whatever the arrays' alignment, and a squared norm is the dot product of an
// array with itself (the same products, pmul(a, a) and a * a). Several such sums in turn wait on
// the latency of their additions one after the other; SumsInEigensOrder runs them side by side,
// with the same packet type and the same operations in the same order, so each result keeps the
// bits of the Eigen call it replaces when its terms are computed as Eigen computes them
// (tests/algorithms/common/eigen_sums_test.cpp and tests/algorithms/allan/deviation_test.cpp hold
// the callers to them). The packet type is Eigen's for the build (SSE2, AVX or AVX-512).
#pragma once

#include <Eigen/Core>
#include <type_traits>

namespace fogpipe {

/// out[k] = the sum over i < n of term k's element i, added in the order of Eigen's reduction
/// (above): term(k, i, Packet()) gives elements i..i+size-1 of term k as Eigen's packet,
/// term(k, i, 0.0) element i alone, each computed as Eigen evaluates the expression it stands for.
/// Zeros for n = 0.
template <int K, typename Term>
inline void SumsInEigensOrder(Eigen::Index n, const Term& term, double (&out)[K]) {
  namespace ei = Eigen::internal;
  using Packet = ei::packet_traits<double>::type;
  constexpr Eigen::Index kP = ei::packet_traits<double>::size;
  for (int k = 0; k < K; ++k) out[k] = 0.0;
  if (n <= 0) return;
  const Eigen::Index end2 = n / (2 * kP) * (2 * kP), end1 = n / kP * kP;
  Eigen::Index first_scalar = 1;
  if (end1 > 0) {
    Packet sum0[K];
    for (int k = 0; k < K; ++k) sum0[k] = term(k, 0, Packet());
    if (end1 > kP) {
      Packet sum1[K];
      for (int k = 0; k < K; ++k) sum1[k] = term(k, kP, Packet());
      for (Eigen::Index i = 2 * kP; i < end2; i += 2 * kP) {
        for (int k = 0; k < K; ++k) {
          sum0[k] = ei::padd(sum0[k], term(k, i, Packet()));
          sum1[k] = ei::padd(sum1[k], term(k, i + kP, Packet()));
        }
      }
      for (int k = 0; k < K; ++k) sum0[k] = ei::padd(sum0[k], sum1[k]);
      if (end1 > end2) {
        for (int k = 0; k < K; ++k) sum0[k] = ei::padd(sum0[k], term(k, end2, Packet()));
      }
    }
    for (int k = 0; k < K; ++k) out[k] = ei::predux(sum0[k]);
    first_scalar = end1;
  } else {
    for (int k = 0; k < K; ++k) out[k] = term(k, 0, 0.0);
  }
  for (Eigen::Index i = first_scalar; i < n; ++i) {
    for (int k = 0; k < K; ++k) out[k] += term(k, i, 0.0);
  }
}

/// out[k] = Map<const VectorXd>(a[k], n).dot(Map<const VectorXd>(b[k], n)) for k < K, bit for bit
/// (a[k] == b[k] gives Map(a[k], n).squaredNorm()); zeros for n = 0.
template <int K>
inline void DotsWithEigensOrder(const double* const (&a)[K], const double* const (&b)[K],
                                Eigen::Index n, double (&out)[K]) {
  namespace ei = Eigen::internal;
  SumsInEigensOrder<K>(
      n,
      [&](int k, Eigen::Index i, auto like) {
        using T = decltype(like);
        if constexpr (std::is_same_v<T, double>) {
          return a[k][i] * b[k][i];
        } else {
          return ei::pmul(ei::ploadu<T>(a[k] + i), ei::ploadu<T>(b[k] + i));
        }
      },
      out);
}

}  // namespace fogpipe
