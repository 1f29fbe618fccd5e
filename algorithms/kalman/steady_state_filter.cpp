#include "algorithms/kalman/steady_state_filter.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "algorithms/common/fixed_order.h"

namespace fogpipe::kalman {
namespace {

using fixed_order::Buffer;

// beta_m = sum_{i=m}^{p-1} phi_i G_{i-m} (see the header), in one fixed order for every caller.
inline void Betas(const double* phi, const double* gain, int p, double* beta, int stride) {
  for (int m = 0; m < p; ++m) {
    double b = 0.0;
    for (int i = m; i < p; ++i) b += phi[i] * gain[i - m];
    beta[m * stride] = b;
  }
}

template <int P, bool kStoreInnovations>
void Kernel(const double* z, long long n, double mean, const double* phi_in, const double* gain,
            double* partial, int p_runtime, double* filtered, double* innovations) {
  const int p = P > 0 ? P : p_runtime;
  Buffer<P> phi_buf(p), beta_buf(p), s_buf(p);
  double* phi = phi_buf.get();
  double* beta = beta_buf.get();
  double* s = s_buf.get();
  Betas(phi_in, gain, p, beta, 1);
  for (int m = 0; m < p; ++m) {
    phi[m] = phi_in[m];
    s[m] = partial[m];
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
  for (int m = 0; m < p; ++m) partial[m] = s[m];
}

// Orders up to this run side by side (state on the stack); higher ones one lane at a time.
constexpr int kMaxLaneOrder = 32;
constexpr int kLanes = 4;
// Four doubles, one per lane (GCC/Clang vector extension: one AVX2 register; element-wise IEEE
// arithmetic, so each lane computes exactly what the scalar Kernel computes).
typedef double Lanes __attribute__((vector_size(kLanes * sizeof(double))));

// Up to four filters side by side, `active` of them real (the others have gain 0 and no output).
// The state s_j of all four lanes is one vector, so every update of the recursion is one vector
// operation and the state stays in registers. P > 0: the order at compile time (loops unrolled);
// P == 0: runtime p.
// Interleaved (all four lanes active, lane m's sum at lanes[0].sum + m, one stride): the four
// estimates of a sample are added to their sums with one vector load, add and store instead of
// four extracted scalars (measured: half of the loop at low orders). Each sum element still gets
// the same one addition.
template <int P, bool kInterleaved>
void AddLanes(const double* z, long long n, const double* phi, int p_runtime,
              const SteadyStateLane* lanes, int active) {
  const int p = P > 0 ? P : p_runtime;
  Lanes s[kMaxLaneOrder], beta[kMaxLaneOrder], phi_v[kMaxLaneOrder];
  Lanes g0 = {}, mean = {};
  double* out[kLanes] = {};
  long long stride[kLanes] = {};
  for (int j = 0; j < p; ++j) {
    s[j] = Lanes{};
    beta[j] = Lanes{};
    phi_v[j] = Lanes{} + phi[j];
  }
  for (int m = 0; m < active; ++m) {
    const double* gain = lanes[m].gain->data();
    double b[kMaxLaneOrder];
    Betas(phi, gain, p, b, 1);
    g0[m] = gain[0];
    mean[m] = lanes[m].mean;
    out[m] = lanes[m].sum;
    stride[m] = lanes[m].sum_stride;
    for (int j = 0; j < p; ++j) {
      beta[j][m] = b[j];
      s[j][m] = lanes[m].partial[j];
    }
  }
  Lanes square_sum = {};
  for (long long k = 0; k < n; ++k) {
    const Lanes pred = s[0];
    const Lanes e = (z[k] - mean) - pred;
    const Lanes deviation = pred + g0 * e;
    const Lanes est = deviation + mean;
    square_sum += deviation * deviation;
    for (int j = 0; j + 1 < p; ++j) s[j] = (phi_v[j] * pred + s[j + 1]) + beta[j] * e;
    s[p - 1] = phi_v[p - 1] * pred + beta[p - 1] * e;
    if constexpr (kInterleaved) {
      double* sum = out[0] + k * stride[0];
      Lanes acc;
      std::memcpy(&acc, sum, sizeof(acc));
      acc += est;
      std::memcpy(sum, &acc, sizeof(acc));
    } else {
      for (int m = 0; m < active; ++m) out[m][k * stride[m]] += est[m];
    }
  }
  for (int m = 0; m < active; ++m) {
    for (int j = 0; j < p; ++j) lanes[m].partial[j] = s[j][m];
    if (lanes[m].square_sum) *lanes[m].square_sum += square_sum[m];
  }
}

}  // namespace

void AddSteadyStateFilters(const double* z, long long n, const Eigen::VectorXd& phi,
                           const std::vector<SteadyStateLane>& lanes) {
  const int p = static_cast<int>(phi.size());
  if (p > kMaxLaneOrder) {
    std::vector<double> estimates(static_cast<std::size_t>(n));
    for (const SteadyStateLane& lane : lanes) {
      SteadyStateFilterFromPartial(z, n, lane.mean, phi, *lane.gain, lane.partial, estimates.data(),
                                   nullptr);
      double square_sum = 0.0;
      for (long long k = 0; k < n; ++k) {
        lane.sum[k * lane.sum_stride] += estimates[k];
        square_sum += (estimates[k] - lane.mean) * (estimates[k] - lane.mean);
      }
      if (lane.square_sum) *lane.square_sum += square_sum;
    }
    return;
  }
  fixed_order::WithWideFixedOrder(p, [&](auto order) {
    constexpr int kP = decltype(order)::value;
    for (std::size_t i = 0; i < lanes.size(); i += kLanes) {
      const int active = static_cast<int>(std::min<std::size_t>(kLanes, lanes.size() - i));
      bool interleaved = active == kLanes;
      for (int m = 1; m < active && interleaved; ++m) {
        interleaved =
            lanes[i + m].sum == lanes[i].sum + m && lanes[i + m].sum_stride == lanes[i].sum_stride;
      }
      if (interleaved) {
        AddLanes<kP, true>(z, n, phi.data(), p, lanes.data() + i, active);
      } else {
        AddLanes<kP, false>(z, n, phi.data(), p, lanes.data() + i, active);
      }
    }
  });
}

void PartialPredictions(const Eigen::VectorXd& phi, const Eigen::VectorXd& state, double* partial) {
  const int p = static_cast<int>(phi.size());
  for (int m = 0; m < p; ++m) {
    double sm = 0.0;
    for (int i = m; i < p; ++i) sm += phi[i] * state[i - m];
    partial[m] = sm;
  }
}

void SteadyStateFilterFromPartial(const double* z, long long n, double mean,
                                  const Eigen::VectorXd& phi, const Eigen::VectorXd& gain,
                                  double* partial, double* filtered, double* innovations) {
  const int p = static_cast<int>(phi.size());
  fixed_order::WithFixedOrder(p, [&](auto order) {
    constexpr int kP = decltype(order)::value;
    if (innovations) {
      Kernel<kP, true>(z, n, mean, phi.data(), gain.data(), partial, p, filtered, innovations);
    } else {
      Kernel<kP, false>(z, n, mean, phi.data(), gain.data(), partial, p, filtered, nullptr);
    }
  });
}

void SteadyStateFilter(const double* z, long long n, double mean, const Eigen::VectorXd& phi,
                       const Eigen::VectorXd& gain, const Eigen::VectorXd& state, double* filtered,
                       double* innovations) {
  std::vector<double> partial(static_cast<std::size_t>(phi.size()));
  PartialPredictions(phi, state, partial.data());
  SteadyStateFilterFromPartial(z, n, mean, phi, gain, partial.data(), filtered, innovations);
}

}  // namespace fogpipe::kalman
