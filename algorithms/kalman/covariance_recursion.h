// The time-varying filter's covariance recursion, one step at a time, with the AR order fixed at
// compile time (internal to algorithms/kalman).
//
// One step is PredictCovariance (eq. 8) followed by JosephUpdate (eqs. 9-10), companion.h, computed
// by the kernel kernels::CovarianceStep (algorithms/kernels/kernels.h) with the same bits (tested
// against the two functions). The generic functions spend most of a small-p step on Eigen's
// dynamic-size bookkeeping (resizes, block copies, the mirror pass); the kernel reads the
// prediction's shifted block in place and unrolls every loop. Measured in `fogpipe sweep` (110
// filters per component, up to 4096 time-varying steps each): see the sweep benchmark in
// scripts/benchmark_sweep.sh.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <vector>

#include "algorithms/kalman/companion.h"
#include "algorithms/kernels/kernels.h"

namespace fogpipe::kalman::internal {

/// One double per recursion (algorithms/kernels/lanes.h).
using CovarianceLanes4 = kernels::Lanes4;

/// P(k|k) of the companion model and the gain G(k), advanced one sample per Step(). P > 0: order P
/// at compile time; P == 0: runtime order (PredictCovariance and JosephUpdate themselves).
template <int P>
class CovarianceRecursion : public kernels::CovarianceStep<P, double> {
 public:
  static constexpr int kOrder = P;
  /// filtered0: P(0|0), p x p symmetric; phi: the AR coefficients (p of them).
  CovarianceRecursion(const Eigen::MatrixXd& filtered0, const Eigen::VectorXd& phi, double q,
                      double r) {
    this->q = q;
    this->r = r;
    for (int i = 0; i < P; ++i) this->phi[i] = phi[i];
    for (int j = 0; j < P; ++j)
      for (int i = 0; i < P; ++i) this->pf[j * P + i] = filtered0(i, j);
  }

  /// G(k) of the last Step(), P doubles.
  const double* gain() const { return this->g; }
};

/// Four CovarianceRecursion<P> of the same AR model (P > 0) with their own P(0|0), q and r, side by
/// side: each lane gives the bits of its own CovarianceRecursion<P> (tested). The covariance
/// recursion does not depend on the data, and it is the O(p^2) part of a time-varying filter step,
/// so a bank of filters of one model (a sweep's q/R settings) can compute four gain sequences for
/// the price of one. Lanes from `active` on repeat lane 0 (their results are ignored).
template <int P>
class CovarianceLanes : public kernels::CovarianceStep<P, CovarianceLanes4> {
 public:
  static_assert(P > 0, "the lanes need the order at compile time");
  CovarianceLanes(const Eigen::MatrixXd* const filtered0[4], const Eigen::VectorXd& phi,
                  const double q[4], const double r[4], int active) {
    for (int i = 0; i < P; ++i) this->phi[i] = CovarianceLanes4{} + phi[i];
    for (int m = 0; m < 4; ++m) {
      const int from = m < active ? m : 0;
      this->q[m] = q[from];
      this->r[m] = r[from];
      for (int j = 0; j < P; ++j)
        for (int i = 0; i < P; ++i) this->pf[j * P + i][m] = (*filtered0[from])(i, j);
    }
  }

  /// G(k) of the last Step(): gain()[i][m] is element i of lane m's gain.
  const CovarianceLanes4* gain() const { return this->g; }
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
