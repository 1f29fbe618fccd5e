// The time-varying filter's covariance recursion, one step at a time, with the AR order fixed at
// compile time (internal to algorithms/kalman).
//
// One step is PredictCovariance (eq. 8) followed by JosephUpdate (eqs. 9-10), companion.h: the same
// operations on the same operands in the same order, every multiply-add spelled out (mul_add.h),
// so the same bits (tested against the two functions), fused and on plain arrays. The generic
// functions spend most of a small-p step on Eigen's dynamic-size bookkeeping (resizes, block
// copies, the mirror pass); here the prediction's shifted block is read in place instead of copied,
// and for P > 0 every loop is unrolled. Measured in `fogpipe sweep` (110 filters per component, up
// to 4096 time-varying steps each): see the sweep benchmark in scripts/benchmark_sweep.sh.
#pragma once

#include <Eigen/Core>
#ifdef __FMA__
#include <immintrin.h>
#endif
#include <algorithm>
#include <cstddef>
#include <vector>

#include "algorithms/common/lanes.h"
#include "algorithms/kalman/companion.h"
#include "algorithms/kalman/mul_add.h"

namespace fogpipe::kalman::internal {

/// One double per recursion (algorithms/common/lanes.h).
using CovarianceLanes4 = Lanes4;

/// MulAdd (mul_add.h) of each lane: one fused multiply-add per element where the CPU has them, as
/// the scalar MulAdd, so each lane rounds exactly as the scalar code does.
inline CovarianceLanes4 MulAdd(CovarianceLanes4 a, CovarianceLanes4 b, CovarianceLanes4 c) {
#ifdef __FMA__
  return CovarianceLanes4(_mm256_fmadd_pd(__m256d(a), __m256d(b), __m256d(c)));
#else
  return a * b + c;
#endif
}

/// One step of the covariance recursion at order P (> 0) on values of type T: double, or
/// CovarianceLanes4 for four recursions side by side, each lane computing exactly what T = double
/// computes (the same operations on its operands in the same order, every multiply-add a MulAdd).
template <int P, typename T>
class CovarianceStep {
 public:
  /// P(k|k-1) = A P(k-1|k-1) A' + Q, then S = P00(k|k-1) + R, G = P(:,0)(k|k-1) / S and the
  /// Joseph-form P(k|k). Returns S.
  T Step() {
    // Column 0 of P(k|k-1): c_0 = phi' P phi + q, c_i = (phi' P)(i-1) (PredictCovariance's order:
    // v_j summed over i ascending, the top summed over j ascending).
    alignas(64) T c[P];
    T top = T{};
    for (int j = 0; j < P; ++j) {
      T v = T{};
      for (int i = 0; i < P; ++i) v = MulAdd(phi_[i], pf_[j * P + i], v);
      top = MulAdd(v, phi_[j], top);
      if (j + 1 < P) c[j + 1] = v;
    }
    c[0] = top + q_;
    const T s = c[0] + r_;
    for (int i = 0; i < P; ++i) g_[i] = c[i] / s;
    // P(k|k)(i, j), i >= j (JosephUpdate's expression): P(k|k-1)(i, j) is c_i in column 0 and
    // P(k-1|k-1)(i-1, j-1) elsewhere (the shift of A P A'). Written to the other buffer, then
    // mirrored.
    alignas(64) T next[P * P];
    for (int j = 0; j < P; ++j) {
      const T cj = c[j];
      for (int i = j; i < P; ++i) {
        const T predicted = j == 0 ? c[i] : pf_[(j - 1) * P + (i - 1)];
        const T t = MulAdd(-g_[i], cj, predicted);
        next[j * P + i] = MulAdd(s * g_[i], g_[j], MulAdd(-c[i], g_[j], t));
      }
    }
    for (int j = 0; j < P; ++j) {
      for (int i = j; i < P; ++i) {
        pf_[j * P + i] = next[j * P + i];
        pf_[i * P + j] = next[j * P + i];
      }
    }
    return s;
  }

 protected:
  T q_ = T{}, r_ = T{};
  alignas(64) T phi_[P];
  alignas(64) T pf_[P * P];  // P(k|k), column-major, both triangles
  alignas(64) T g_[P];
};

/// P(k|k) of the companion model and the gain G(k), advanced one sample per Step(). P > 0: order P
/// at compile time; P == 0: runtime order (PredictCovariance and JosephUpdate themselves).
template <int P>
class CovarianceRecursion : public CovarianceStep<P, double> {
 public:
  static constexpr int kOrder = P;
  /// filtered0: P(0|0), p x p symmetric; phi: the AR coefficients (p of them).
  CovarianceRecursion(const Eigen::MatrixXd& filtered0, const Eigen::VectorXd& phi, double q,
                      double r) {
    this->q_ = q;
    this->r_ = r;
    for (int i = 0; i < P; ++i) this->phi_[i] = phi[i];
    for (int j = 0; j < P; ++j)
      for (int i = 0; i < P; ++i) this->pf_[j * P + i] = filtered0(i, j);
  }

  /// G(k) of the last Step(), P doubles.
  const double* gain() const { return this->g_; }
};

/// Four CovarianceRecursion<P> of the same AR model (P > 0) with their own P(0|0), q and r, side by
/// side: each lane gives the bits of its own CovarianceRecursion<P> (tested). The covariance
/// recursion does not depend on the data, and it is the O(p^2) part of a time-varying filter step,
/// so a bank of filters of one model (a sweep's q/R settings) can compute four gain sequences for
/// the price of one. Lanes from `active` on repeat lane 0 (their results are ignored).
template <int P>
class CovarianceLanes : public CovarianceStep<P, CovarianceLanes4> {
 public:
  static_assert(P > 0, "the lanes need the order at compile time");
  CovarianceLanes(const Eigen::MatrixXd* const filtered0[4], const Eigen::VectorXd& phi,
                  const double q[4], const double r[4], int active) {
    for (int i = 0; i < P; ++i) this->phi_[i] = CovarianceLanes4{} + phi[i];
    for (int m = 0; m < 4; ++m) {
      const int from = m < active ? m : 0;
      this->q_[m] = q[from];
      this->r_[m] = r[from];
      for (int j = 0; j < P; ++j)
        for (int i = 0; i < P; ++i) this->pf_[j * P + i][m] = (*filtered0[from])(i, j);
    }
  }

  /// G(k) of the last Step(): gain()[i][m] is element i of lane m's gain.
  const CovarianceLanes4* gain() const { return this->g_; }
};

template <>
class CovarianceRecursion<0> {
 public:
  static constexpr int kOrder = 0;
  CovarianceRecursion(const Eigen::MatrixXd& filtered0, const Eigen::VectorXd& phi, double q,
                      double r)
      : phi_(phi), q_(q), r_(r), pf_(filtered0), g_(phi.size()) {}
  double Step() {
    PredictCovariance(pf_, phi_, q_, &pp_);
    return JosephUpdate(pp_, r_, &g_, &pf_);
  }
  const double* gain() const { return g_.data(); }

 private:
  Eigen::VectorXd phi_;
  double q_, r_;
  Eigen::MatrixXd pf_, pp_;
  Eigen::VectorXd g_;
};

}  // namespace fogpipe::kalman::internal
