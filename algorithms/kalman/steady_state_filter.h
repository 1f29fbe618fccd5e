// The constant-gain (steady-state) AR Kalman loop, the hot path of fogpipe's filtering:
//
//   pred(k) = phi' X(k-1|k-1),  e(k) = z(k) - mean - pred(k),  X(k|k) = A X(k-1|k-1) + G e(k),
//   out(k) = x(k|k) + mean = pred(k) + G_0 e(k) + mean.
//
// Latency, not arithmetic, limits this loop: every prediction needs the previous update, and the
// plain form (a dot product, then the update) puts p multiplications and a log2(p) addition tree
// on that chain. The loop therefore carries, instead of X(k|k), the partial predictions
//
//   s_m(k) = sum_{i=m}^{p-1} phi_i x_{i-m}(k|k),   m = 0..p-1,   pred(k+1) = s_0(k),
//
// which obey (substitute x_0(k|k) = pred(k) + G_0 e(k), x_j(k|k) = x_{j-1}(k-1|k-1) + G_j e(k))
//
//   s_m(k) = phi_m pred(k) + s_{m+1}(k-1) + beta_m e(k),   beta_m = sum_{i=m}^{p-1} phi_i G_{i-m},
//
// the transposed direct form of the filter's innovations recursion (Oppenheim & Schafer,
// "Discrete-Time Signal Processing", sec. 6.5). It is an exact regrouping of phi' X(k|k); the
// dependency chain per sample is one subtraction and one fused multiply-add, whatever p. The loop
// starts from any state X (the time-varying filter's at the switch), with no Eigen temporaries per
// sample; orders 1..8 use fixed-size kernels whose state lives in registers.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace fogpipe::kalman {

/// Runs the loop over n samples of z from the state X(k-1|k-1) = `state` (size p). `filtered`
/// receives n estimates of x(k); `innovations`, if not null, the n e(k) (for the smoother).
/// phi and gain have size p >= 1. Equals PartialPredictions + SteadyStateFilterFromPartial.
void SteadyStateFilter(const double* z, long long n, double mean, const Eigen::VectorXd& phi,
                       const Eigen::VectorXd& gain, const Eigen::VectorXd& state, double* filtered,
                       double* innovations);

/// Whether the loop is stable as it runs. Substituting e(k) = z(k) - mean - pred(k) above,
/// pred(k+1) = sum_m (phi_m - beta_m) pred(k-m) + input, so the loop's characteristic polynomial is
/// z^p - sum_m (phi_m - beta_m) z^{p-1-m} with the betas exactly as the loop computes them: every
/// root must be inside the unit circle, decided in extended precision (ar/stationarity.h). A
/// stabilizing DARE gain makes it so in exact arithmetic, but when the model's roots cluster near
/// z = 1 (slow components) the rounded phi and beta can put the loop's roots outside, and the
/// estimate then grows like modulus^k. `modulus`, if not null, receives the largest root modulus
/// when the loop is not stable (its bisection is not spent on the loops that are).
bool ConstantGainLoopStable(const Eigen::VectorXd& phi, const Eigen::VectorXd& gain,
                            double* modulus = nullptr);

/// The loop's own state for X(k|k) = `state`: partial[m] = s_m(k) (p doubles, see above).
void PartialPredictions(const Eigen::VectorXd& phi, const Eigen::VectorXd& state, double* partial);

/// SteadyStateFilter carried in the loop's own state: `partial` (p doubles) holds s at entry and is
/// left holding s after the n samples, so consecutive calls continue one run to the last bit, and
/// AddSteadyStateFilters can continue it side by side with other filters.
void SteadyStateFilterFromPartial(const double* z, long long n, double mean,
                                  const Eigen::VectorXd& phi, const Eigen::VectorXd& gain,
                                  double* partial, double* filtered, double* innovations);

/// One filter of AddSteadyStateFilters: its constant gain (size p), the mean removed from z before
/// filtering and added back, where its output is added (n doubles), and its loop state `partial`
/// (p doubles: s at entry, left holding s after the n samples).
struct SteadyStateLane {
  const Eigen::VectorXd* gain = nullptr;
  double mean = 0.0;
  double* sum = nullptr;
  double* partial = nullptr;
  /// If set, sum over the samples of (estimate - mean)^2 is added to it (a divergence check).
  double* square_sum = nullptr;
  /// The k-th estimate is added to sum[k * sum_stride]. Four lanes whose sums are interleaved
  /// (lane m's at sum + m, the same stride) add with one vector operation per sample.
  long long sum_stride = 1;
};

/// Several constant-gain filters of the same AR model (e.g. the q/R settings of a sweep) over the
/// same z, each from its own state, each adding its estimates of x(k) to lane.sum[k]. The filters
/// run four at a time in one pass: the same recursion as SteadyStateFilterFromPartial with the four
/// lanes side by side (one SIMD register on AVX2), so four independent dependency chains overlap
/// and the per-filter cost drops well below the latency-bound single loop; with interleaved sums,
/// up to three such groups share one loop (two from order 7). Each lane's arithmetic is the single
/// loop's, in the same order: the estimates are equal to the last bit (tested).
void AddSteadyStateFilters(const double* z, long long n, const Eigen::VectorXd& phi,
                           const std::vector<SteadyStateLane>& lanes);

}  // namespace fogpipe::kalman
