#include "algorithms/kalman/steady_state_filter.h"

#include <vector>

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

// Orders up to this run side by side (state on the stack); higher ones one lane at a time.
constexpr int kMaxLaneOrder = 32;

// L filters side by side; state and beta lane-minor (index j * L + lane) so that every update over
// the lanes is one contiguous vector operation. They live in local arrays, which the compiler
// knows the output stores cannot alias, so the state stays in registers across the stores.
// P > 0: the order at compile time (loops unrolled, state in registers); P == 0: runtime p.
template <int L, int P>
void AddLanes(const double* z, long long n, const double* phi, int p_runtime,
              const SteadyStateLane* lanes) {
  const int p = P > 0 ? P : p_runtime;
  double s[kMaxLaneOrder * L] = {}, beta[kMaxLaneOrder * L], g0[L], mean[L];
  double* out[L];
  for (int m = 0; m < L; ++m) {
    const double* gain = lanes[m].gain->data();
    g0[m] = gain[0];
    mean[m] = lanes[m].mean;
    out[m] = lanes[m].sum;
    for (int j = 0; j < p; ++j) {
      double b = 0.0;
      for (int i = j; i < p; ++i) b += phi[i] * gain[i - j];
      beta[j * L + m] = b;
    }
  }
  double phi_local[kMaxLaneOrder];
  for (int j = 0; j < p; ++j) phi_local[j] = phi[j];
  for (long long k = 0; k < n; ++k) {
    double pred[L], e[L], est[L];
    const double zk = z[k];
    for (int m = 0; m < L; ++m) {
      pred[m] = s[m];
      e[m] = (zk - mean[m]) - pred[m];
      est[m] = (pred[m] + g0[m] * e[m]) + mean[m];
    }
    for (int j = 0; j + 1 < p; ++j) {
      for (int m = 0; m < L; ++m) {
        s[j * L + m] = (phi_local[j] * pred[m] + s[(j + 1) * L + m]) + beta[j * L + m] * e[m];
      }
    }
    for (int m = 0; m < L; ++m) {
      s[(p - 1) * L + m] = phi_local[p - 1] * pred[m] + beta[(p - 1) * L + m] * e[m];
    }
    for (int m = 0; m < L; ++m) out[m][k] += est[m];
  }
}

// Compile-time orders 1..12 for the side-by-side filters (the sweep's default orders are 2..12),
// runtime order (0) above.
template <typename F>
void WithLaneOrder(int p, F&& f) {
  if (p <= internal::kMaxFixedOrder) return internal::WithFixedOrder(p, f);
  switch (p) {
    case 9:
      return f(std::integral_constant<int, 9>());
    case 10:
      return f(std::integral_constant<int, 10>());
    case 11:
      return f(std::integral_constant<int, 11>());
    case 12:
      return f(std::integral_constant<int, 12>());
    default:
      return f(std::integral_constant<int, 0>());
  }
}

}  // namespace

void AddSteadyStateFilters(const double* z, long long n, const Eigen::VectorXd& phi,
                           const std::vector<SteadyStateLane>& lanes) {
  const int p = static_cast<int>(phi.size());
  if (p > kMaxLaneOrder) {
    std::vector<double> estimates(static_cast<std::size_t>(n));
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p);
    for (const SteadyStateLane& lane : lanes) {
      SteadyStateFilter(z, n, lane.mean, phi, *lane.gain, zero, estimates.data(), nullptr);
      for (long long k = 0; k < n; ++k) lane.sum[k] += estimates[k];
    }
    return;
  }
  WithLaneOrder(p, [&](auto order) {
    constexpr int kP = decltype(order)::value;
    std::size_t i = 0;
    for (; i + 4 <= lanes.size(); i += 4) AddLanes<4, kP>(z, n, phi.data(), p, lanes.data() + i);
    switch (lanes.size() - i) {
      case 3:
        AddLanes<3, kP>(z, n, phi.data(), p, lanes.data() + i);
        break;
      case 2:
        AddLanes<2, kP>(z, n, phi.data(), p, lanes.data() + i);
        break;
      case 1:
        AddLanes<1, kP>(z, n, phi.data(), p, lanes.data() + i);
        break;
      default:
        break;
    }
  });
}

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
