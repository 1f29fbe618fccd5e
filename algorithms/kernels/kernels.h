// The numeric kernels that run both alone and four side by side, each written once as a template
// on its value type T: T = double is the scalar reference, T = Lanes4 (lanes.h) the vector
// variant, four independent recursions or sums in the elements of one vector value. Both are the
// same expression in the same order, and the build never contracts (lanes.h), so each element of
// the variant has its reference's bits on every build, native or portable
// (tests/algorithms/kernels/kernels_test.cpp holds every variant to its reference).
//
// Callers: the AR Kalman filter's covariance recursion (kalman/covariance_recursion.h) and its
// constant-gain loop (kalman/steady_state_filter.cpp), the AR fit's free runs and one-step
// residuals (ar/diagnostics.cpp), Mod AVAR's window sums (allan/noise_id.cpp), the angle
// quantizer's convolution on its grid (model/angle_quantizer.cpp).
#pragma once

#include "algorithms/kernels/lanes.h"

namespace fogpipe::kernels {

/// One step of the time-varying Kalman filter's covariance recursion for the AR(P) companion model
/// (P > 0): P(k|k-1) = A P(k-1|k-1) A' + Q (eq. 8), then S = P00(k|k-1) + R, G = P(:,0)(k|k-1) / S
/// and the Joseph-form P(k|k) (eqs. 9-10). The same operations on the same operands in the same
/// order as kalman::PredictCovariance followed by kalman::JosephUpdate (companion.h), every
/// multiply-add a MulAdd, fused and on plain arrays: the prediction's shifted block is read in
/// place instead of copied, and every loop is unrolled.
template <int P, typename T>
struct CovarianceStep {
  /// Advances pf from P(k-1|k-1) to P(k|k) and sets g to G(k). Returns S.
  T Step() {
    // Column 0 of P(k|k-1): c_0 = phi' P phi + q, c_i = (phi' P)(i-1) (PredictCovariance's order:
    // v_j summed over i ascending, the top summed over j ascending).
    alignas(64) T c[P];
    T top = T{};
    for (int j = 0; j < P; ++j) {
      T v = T{};
      for (int i = 0; i < P; ++i) v = MulAdd(phi[i], pf[j * P + i], v);
      top = MulAdd(v, phi[j], top);
      if (j + 1 < P) c[j + 1] = v;
    }
    c[0] = top + q;
    const T s = c[0] + r;
    for (int i = 0; i < P; ++i) g[i] = c[i] / s;
    // P(k|k)(i, j), i >= j (JosephUpdate's expression): P(k|k-1)(i, j) is c_i in column 0 and
    // P(k-1|k-1)(i-1, j-1) elsewhere (the shift of A P A'). Written to the other buffer, then
    // mirrored.
    alignas(64) T next[P * P];
    for (int j = 0; j < P; ++j) {
      const T cj = c[j];
      for (int i = j; i < P; ++i) {
        const T predicted = j == 0 ? c[i] : pf[(j - 1) * P + (i - 1)];
        const T t = MulAdd(-g[i], cj, predicted);
        next[j * P + i] = MulAdd(s * g[i], g[j], MulAdd(-c[i], g[j], t));
      }
    }
    for (int j = 0; j < P; ++j) {
      for (int i = j; i < P; ++i) {
        pf[j * P + i] = next[j * P + i];
        pf[i * P + j] = next[j * P + i];
      }
    }
    return s;
  }

  T q = T{}, r = T{};
  alignas(64) T phi[P];
  alignas(64) T pf[P * P];  ///< P(k|k), column-major, both triangles
  alignas(64) T g[P];       ///< G(k) of the last Step()
};

/// One sample of the constant-gain Kalman loop on its partial predictions s[0..p)
/// (kalman/steady_state_filter.h): with pred = s[0] and the innovation e = (z - mean) - pred,
/// returns the estimate's deviation from the mean, pred + G_0 e, stores e in *innovation and
/// advances s: s_m = phi_m pred + s_{m+1} + beta_m e. The chain from one sample to the next is
/// one subtraction and one fused multiply-add.
template <typename T>
inline T SteadyStateSample(double z, T mean, T g0, const T* phi, const T* beta, int p, T* s,
                           T* innovation) {
  const T pred = s[0];
  const T e = (Splat<T>(z) - mean) - pred;
  for (int m = 0; m + 1 < p; ++m) s[m] = MulAdd(beta[m], e, MulAdd(phi[m], pred, s[m + 1]));
  s[p - 1] = MulAdd(beta[p - 1], e, phi[p - 1] * pred);
  *innovation = e;
  return MulAdd(g0, e, pred);
}

/// One sample of an AR model's free run (ar/diagnostics.h, the simulation fit): with h[0..p) the
/// last p values s_{t-1}..s_{t-p}, returns s_t = sum_i phi_i s_{t-1-i}, phi_0 s_{t-1} added last
/// (the older terms are off the loop-carried chain), and shifts it into h.
template <typename T>
inline T FreeRunSample(const T* phi, int p, T* h) {
  T older = T{};
  for (int i = 1; i < p; ++i) older += phi[i] * h[i];
  const T s = phi[0] * h[0] + older;
  for (int i = p - 1; i >= 1; --i) h[i] = h[i - 1];
  h[0] = s;
  return s;
}

/// An AR model's one-step residual at x_t (ar/diagnostics.h): (x_t - mean) - sum_i phi_i (x_{t-i}
/// - mean), the terms subtracted in order i = 1..p. x(i) gives x_{t-i} as a T: one sample, or
/// four consecutive samples' residuals at once.
template <typename T, typename Series>
inline T ArResidual(Series&& x, const double* phi, int p, double mean) {
  const T m = Splat<T>(mean);
  T acc = x(0) - m;
  for (int i = 1; i <= p; ++i) acc -= Splat<T>(phi[i - 1]) * (x(i) - m);
  return acc;
}

/// Outputs of a discrete convolution on a grid (model/angle_quantizer.cpp's transition):
/// sum[v] = sum_k weight[k] x(k, v) over the taps k in [k0, k1), in order from 0, each product
/// rounded and then added. x(k, v) gives group v's input for tap k as a T: one cell, or four
/// consecutive cells. Groups side by side are independent chains of additions.
template <typename T, int kGroups, typename Series>
inline void ConvolutionSums(Series&& x, const double* weight, int k0, int k1, T* sum) {
  for (int v = 0; v < kGroups; ++v) sum[v] = T{};
  for (int k = k0; k < k1; ++k) {
    const T w = Splat<T>(weight[k]);
    for (int v = 0; v < kGroups; ++v) sum[v] = sum[v] + w * x(k, v);
  }
}

/// One window of Mod AVAR's sliding block sums (allan/noise_id.cpp): adds the window's squared
/// third difference of the block sums s0, s1, s2 to sum.
template <typename T>
inline void AddModifiedWindow(T s0, T s1, T s2, T* sum) {
  const T v = s2 - 2.0 * s1 + s0;
  *sum += v * v;
}

/// Slides the block sums by one sample: a = x_j, b = x_{j+m}, c = x_{j+2m}, e = x_{j+3m}.
template <typename T>
inline void SlideModifiedWindow(T a, T b, T c, T e, T* s0, T* s1, T* s2) {
  *s0 += b - a, *s1 += c - b, *s2 += e - c;
}

}  // namespace fogpipe::kernels
