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
#include <algorithm>
#include <cstddef>
#include <vector>

#include "algorithms/kalman/companion.h"
#include "algorithms/kalman/mul_add.h"

namespace fogpipe::kalman::internal {

/// P(k|k) of the companion model and the gain G(k), advanced one sample per Step(). P > 0: order P
/// at compile time; P == 0: runtime order (PredictCovariance and JosephUpdate themselves).
template <int P>
class CovarianceRecursion {
 public:
  static constexpr int kOrder = P;
  /// filtered0: P(0|0), p x p symmetric; phi: the AR coefficients (p of them).
  CovarianceRecursion(const Eigen::MatrixXd& filtered0, const Eigen::VectorXd& phi, double q,
                      double r)
      : q_(q), r_(r) {
    for (int i = 0; i < P; ++i) phi_[i] = phi[i];
    for (int j = 0; j < P; ++j)
      for (int i = 0; i < P; ++i) pf_[j * P + i] = filtered0(i, j);
  }

  /// P(k|k-1) = A P(k-1|k-1) A' + Q, then S = P00(k|k-1) + R, G = P(:,0)(k|k-1) / S and the
  /// Joseph-form P(k|k). Returns S.
  double Step() {
    // Column 0 of P(k|k-1): c_0 = phi' P phi + q, c_i = (phi' P)(i-1) (PredictCovariance's order:
    // v_j summed over i ascending, the top summed over j ascending).
    alignas(64) double c[P];
    double top = 0.0;
    for (int j = 0; j < P; ++j) {
      double v = 0.0;
      for (int i = 0; i < P; ++i) v = MulAdd(phi_[i], pf_[j * P + i], v);
      top = MulAdd(v, phi_[j], top);
      if (j + 1 < P) c[j + 1] = v;
    }
    c[0] = top + q_;
    const double s = c[0] + r_;
    for (int i = 0; i < P; ++i) g_[i] = c[i] / s;
    // P(k|k)(i, j), i >= j (JosephUpdate's expression): P(k|k-1)(i, j) is c_i in column 0 and
    // P(k-1|k-1)(i-1, j-1) elsewhere (the shift of A P A'). Written to the other buffer, then
    // mirrored.
    alignas(64) double next[P * P];
    for (int j = 0; j < P; ++j) {
      const double cj = c[j];
      for (int i = j; i < P; ++i) {
        const double predicted = j == 0 ? c[i] : pf_[(j - 1) * P + (i - 1)];
        const double t = MulAdd(-g_[i], cj, predicted);
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

  /// G(k) of the last Step(), P doubles.
  const double* gain() const { return g_; }

 private:
  double q_, r_;
  alignas(64) double phi_[P];
  alignas(64) double pf_[P * P];  // P(k|k), column-major, both triangles
  alignas(64) double g_[P];
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
