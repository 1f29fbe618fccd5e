#include "algorithms/kalman/rts_smoother.h"

#include <cmath>
#include <limits>

#include "algorithms/common/fixed_order.h"
#include "algorithms/kalman/companion.h"

namespace fogpipe::kalman {
namespace {

// r <- L' r + H' e / S with L' r = (I - H' G') A' r; (A' r)_j = phi_j r_0 + r_{j+1}.
// Returns G' r_new, so that x_0(k|N) = z - e + S * (returned value).
inline double BackwardStep(const double* phi, const double* g, int p, double e, double s,
                           double* r) {
  const double r0 = r[0];
  double gv = 0.0;
  for (int j = 0; j < p; ++j) {
    const double v = phi[j] * r0 + (j + 1 < p ? r[j + 1] : 0.0);
    r[j] = v;
    gv += g[j] * v;
  }
  r[0] += e / s - gv;
  double out = 0.0;
  for (int j = 0; j < p; ++j) out += g[j] * r[j];
  return out;
}

// The steady-state part of the backward pass, samples [begin, end) in reverse. Besides r it carries
// t_j = sum_i G_i r_{i+j}, j = 1..p-1, which obey t_j <- (G' shifted phi)_j r_0 + t_{j+1} like the
// r_j themselves; then G' A' r = gphi_0 r_0 + t_1 needs no dot product on the r_0 -> r_0 chain
// (the same regrouping as the forward loop, steady_state_filter.h). With g_v = G' A' r:
//   r_0 <- phi_0 r_0 + r_1 + e/S - g_v,   G' r_new = (1 - G_0) g_v + G_0 e / S.
template <int P>
void SteadyStateBackward(const double* z, double mean, const double* phi_in, const double* g_in,
                         double s, int p_runtime, long long begin, long long end, double* io,
                         double* r_io) {
  const int p = P > 0 ? P : p_runtime;
  fixed_order::Buffer<P> phi_b(p), gphi_b(p), r_b(p), t_b(p);
  double* phi = phi_b.get();
  double* gphi = gphi_b.get();
  double* r = r_b.get();
  double* t = t_b.get();
  for (int j = 0; j < p; ++j) {
    phi[j] = phi_in[j];
    r[j] = r_io[j];
    double a = 0.0, b = 0.0;
    for (int i = 0; i + j < p; ++i) {
      a += g_in[i] * phi_in[i + j];
      b += g_in[i] * r_io[i + j];
    }
    gphi[j] = a;
    t[j] = b;  // t[0] unused
  }
  const double g0 = g_in[0];
  const double inv_s = 1.0 / s;
  for (long long k = end - 1; k >= begin; --k) {
    const double e = io[k];
    const double r0 = r[0];
    const double gv = gphi[0] * r0 + (p > 1 ? t[1] : 0.0);
    const double r0_new = (phi[0] * r0 + (p > 1 ? r[1] : 0.0)) + (e * inv_s - gv);
    for (int j = 1; j + 1 < p; ++j) {
      r[j] = phi[j] * r0 + r[j + 1];
      t[j] = gphi[j] * r0 + t[j + 1];
    }
    if (p > 1) {
      r[p - 1] = phi[p - 1] * r0;
      t[p - 1] = gphi[p - 1] * r0;
    }
    r[0] = r0_new;
    io[k] = ((z[k] - mean - e) + (s * (1.0 - g0) * gv + g0 * e)) + mean;
  }
  for (int j = 0; j < p; ++j) r_io[j] = r[j];
}

}  // namespace

void RtsSmoothInPlace(const Eigen::Ref<const Eigen::VectorXd>& z, double mean,
                      const Eigen::VectorXd& phi, const FilterGainHistory& gains,
                      Eigen::VectorXd* innovations_to_smoothed) {
  Eigen::VectorXd& io = *innovations_to_smoothed;
  const int p = static_cast<int>(phi.size());
  const long long n = io.size();
  std::vector<double> r(p, 0.0);
  const long long m = gains.time_varying_steps;
  const double* g_ss = gains.steady_state_gain.data();
  const double s_ss = gains.steady_state_innovation_variance;
  fixed_order::WithFixedOrder(p, [&](auto order) {
    SteadyStateBackward<decltype(order)::value>(z.data(), mean, phi.data(), g_ss, s_ss, p, m, n,
                                                io.data(), r.data());
  });
  for (long long k = std::min(m, n) - 1; k >= 0; --k) {
    const double e = io[k];
    const double s = gains.time_varying_innovation_variances[k];
    const double* g = gains.time_varying_gains.data() + p * k;
    io[k] = ((z[k] - mean - e) + s * BackwardStep(phi.data(), g, p, e, s, r.data())) + mean;
  }
}

double SteadyStateSmoothedVariance(const Eigen::VectorXd& phi, const DareSolution& dare) {
  const Eigen::Index p = phi.size();
  const Eigen::MatrixXd a = CompanionMatrix(phi);
  Eigen::MatrixXd i_minus_gh = Eigen::MatrixXd::Identity(p, p);
  i_minus_gh.col(0) -= dare.gain;
  Eigen::MatrixXd m = a * i_minus_gh;
  Eigen::MatrixXd nn = Eigen::MatrixXd::Zero(p, p);
  nn(0, 0) = 1.0 / dare.innovation_variance;
  for (int it = 0; it < 64; ++it) {
    const Eigen::MatrixXd next = nn + m.transpose() * nn * m;
    m = (m * m).eval();
    const double change = (next - nn).norm();
    nn = next;
    if (change <= 1e-16 * nn.norm()) {
      const Eigen::MatrixXd& pp = dare.predicted_covariance;
      return pp(0, 0) - (pp.row(0) * nn * pp.col(0))(0, 0);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

bool SmootherContradictsModel(const Eigen::Ref<const Eigen::VectorXd>& z,
                              const Eigen::VectorXd& filtered, const Eigen::VectorXd& smoothed,
                              double* filtered_residual_ms, double* smoothed_residual_ms) {
  *filtered_residual_ms = *smoothed_residual_ms = 0.0;
  if (z.size() == 0) return false;
  *filtered_residual_ms = (z - filtered).squaredNorm() / static_cast<double>(z.size());
  *smoothed_residual_ms = (z - smoothed).squaredNorm() / static_cast<double>(z.size());
  return *smoothed_residual_ms < *filtered_residual_ms;
}

}  // namespace fogpipe::kalman
