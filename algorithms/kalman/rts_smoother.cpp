#include "algorithms/kalman/rts_smoother.h"

#include <cmath>
#include <limits>

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
  for (long long k = n - 1; k >= m; --k) {
    const double e = io[k];
    io[k] = (z[k] - mean - e) + s_ss * BackwardStep(phi.data(), g_ss, p, e, s_ss, r.data());
  }
  for (long long k = std::min(m, n) - 1; k >= 0; --k) {
    const double e = io[k];
    const double s = gains.time_varying_innovation_variances[k];
    const double* g = gains.time_varying_gains.data() + p * k;
    io[k] = (z[k] - mean - e) + s * BackwardStep(phi.data(), g, p, e, s, r.data());
  }
  io.array() += mean;
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

}  // namespace fogpipe::kalman
