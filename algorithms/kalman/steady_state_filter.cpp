#include "algorithms/kalman/steady_state_filter.h"

#include "algorithms/kalman/fixed_order.h"

namespace fogpipe::kalman {
namespace {

using internal::Buffer;

template <int P, bool kStoreInnovations>
void Kernel(const double* z, long long n, double mean, const double* phi_in, const double* gain,
            const double* state, int p_runtime, double* filtered, double* innovations) {
  const int p = P > 0 ? P : p_runtime;
  Buffer<P> phi_buf(p), beta_buf(p), s_buf(p);
  double* phi = phi_buf.get();
  double* beta = beta_buf.get();
  double* s = s_buf.get();
  for (int m = 0; m < p; ++m) {
    phi[m] = phi_in[m];
    double b = 0.0, sm = 0.0;
    for (int i = m; i < p; ++i) {
      b += phi_in[i] * gain[i - m];
      sm += phi_in[i] * state[i - m];
    }
    beta[m] = b;
    s[m] = sm;
  }
  const double g0 = gain[0];
  for (long long k = 0; k < n; ++k) {
    const double pred = s[0];
    const double e = (z[k] - mean) - pred;
    filtered[k] = (pred + g0 * e) + mean;
    if constexpr (kStoreInnovations) innovations[k] = e;
    for (int m = 0; m + 1 < p; ++m) s[m] = (phi[m] * pred + s[m + 1]) + beta[m] * e;
    s[p - 1] = phi[p - 1] * pred + beta[p - 1] * e;
  }
}

}  // namespace

void SteadyStateFilter(const double* z, long long n, double mean, const Eigen::VectorXd& phi,
                       const Eigen::VectorXd& gain, const Eigen::VectorXd& state, double* filtered,
                       double* innovations) {
  const int p = static_cast<int>(phi.size());
  internal::WithFixedOrder(p, [&](auto order) {
    constexpr int kP = decltype(order)::value;
    if (innovations) {
      Kernel<kP, true>(z, n, mean, phi.data(), gain.data(), state.data(), p, filtered, innovations);
    } else {
      Kernel<kP, false>(z, n, mean, phi.data(), gain.data(), state.data(), p, filtered, nullptr);
    }
  });
}

}  // namespace fogpipe::kalman
