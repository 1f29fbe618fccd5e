#include "algorithms/kalman/steady_state_filter.h"

#include <algorithm>
#include <type_traits>
#include <vector>

#include "algorithms/ar/stationarity.h"
#include "algorithms/common/fixed_order.h"
#include "algorithms/kernels/kernels.h"

namespace fogpipe::kalman {
namespace {

using fixed_order::Buffer;

// beta_m = sum_{i=m}^{p-1} phi_i G_{i-m} (see the header), in one fixed order for every caller.
inline void Betas(const double* phi, const double* gain, int p, double* beta, int stride) {
  for (int m = 0; m < p; ++m) {
    double b = 0.0;
    for (int i = m; i < p; ++i) b = kernels::MulAdd(phi[i], gain[i - m], b);
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
    double e;
    filtered[k] = kernels::SteadyStateSample(z[k], mean, g0, phi, beta, p, s, &e) + mean;
    if constexpr (kStoreInnovations) innovations[k] = e;
  }
  for (int m = 0; m < p; ++m) partial[m] = s[m];
}

// Orders up to this run side by side (state on the stack); higher ones one lane at a time.
constexpr int kMaxLaneOrder = 32;
constexpr int kLanes = 4;
// One per lane: each lane computes exactly what the scalar Kernel computes (the same
// kernels::SteadyStateSample, algorithms/kernels/kernels.h).
using Lanes = kernels::Lanes4;

// Up to 4 G filters side by side in G groups of four, `active` of them real (the others have
// gain 0 and no output). The state s_j of each group is one vector, so every update of the
// recursion is one vector operation per group and the state stays in registers; the G groups'
// dependency chains are independent, so at low orders (where one group's loop is bound by the
// latency of its chain, not by its arithmetic) they overlap in the same cycles. P > 0: the order
// at compile time (loops unrolled); P == 0: runtime p.
// Interleaved (lane m's sum at lanes[0].sum + m, one stride, for every lane of the full groups):
// the four estimates of a full group are added to their sums with one vector load, add and store
// instead of four extracted scalars (measured: half of the loop at low orders). A group with fewer
// than four real lanes adds them one by one. Each sum element still gets the same one addition.
template <int P, int G, bool kInterleaved>
FOGPIPE_LANE_KERNEL void AddLanes(const double* z, long long n, const double* phi, int p_runtime,
                                  const SteadyStateLane* lanes, int active) {
  const int p = P > 0 ? P : p_runtime;
  Lanes s[G][kMaxLaneOrder], beta[G][kMaxLaneOrder], phi_v[kMaxLaneOrder];
  Lanes g0[G] = {}, mean[G] = {}, square_sum[G] = {};
  double* out[G * kLanes] = {};
  long long stride[G * kLanes] = {};
  for (int j = 0; j < p; ++j) phi_v[j] = Lanes{} + phi[j];
  for (int g = 0; g < G; ++g) {
    for (int j = 0; j < p; ++j) {
      s[g][j] = Lanes{};
      beta[g][j] = Lanes{};
    }
  }
  for (int l = 0; l < active; ++l) {
    const int g = l / kLanes, m = l % kLanes;
    const double* gain = lanes[l].gain->data();
    double b[kMaxLaneOrder];
    Betas(phi, gain, p, b, 1);
    g0[g][m] = gain[0];
    mean[g][m] = lanes[l].mean;
    out[l] = lanes[l].sum;
    stride[l] = lanes[l].sum_stride;
    for (int j = 0; j < p; ++j) {
      beta[g][j][m] = b[j];
      s[g][j][m] = lanes[l].partial[j];
    }
  }
  const int full_groups = active / kLanes;
  for (long long k = 0; k < n; ++k) {
    const double zk = z[k];
#pragma GCC unroll 4
    for (int g = 0; g < G; ++g) {
      Lanes e;
      const Lanes deviation =
          kernels::SteadyStateSample(zk, mean[g], g0[g], phi_v, beta[g], p, s[g], &e);
      const Lanes est = deviation + mean[g];
      square_sum[g] += deviation * deviation;
      if (kInterleaved && g < full_groups) {
        double* sum = out[g * kLanes] + k * stride[g * kLanes];
        kernels::StoreLanes4(sum, kernels::LoadLanes4(sum) + est);
      } else {
        for (int m = 0; m < kLanes && g * kLanes + m < active; ++m)
          out[g * kLanes + m][k * stride[g * kLanes + m]] += est[m];
      }
    }
  }
  for (int l = 0; l < active; ++l) {
    const int g = l / kLanes, m = l % kLanes;
    for (int j = 0; j < p; ++j) lanes[l].partial[j] = s[g][j][m];
    if (lanes[l].square_sum) *lanes[l].square_sum += square_sum[g][m];
  }
}

// Groups of four lanes run in one loop with interleaved sums, at most this many: the sweep's ten
// filters per model (kalman_benchmark, BM_SideBySide/p/1, ns per filter and sample on the 2-core
// AMD EPYC machine with AVX2: p = 2: 0.82 with one group, 0.58 with two, 0.50 with three; p = 4:
// 0.83, 0.72, 0.54; p = 8: 1.06, 0.84, 0.93; p = 12: 1.34, 1.29, 1.45). At low orders a group's
// loop waits on its chain's latency, which the other groups fill; at high orders the arithmetic
// is the limit and three groups' states no longer fit the registers.
constexpr int MaxGroups(int p) { return p >= 1 && p <= 6 ? 3 : 2; }

// Calls f(std::integral_constant<int, G>) with G = groups, 1 <= groups <= kMax <= 3.
template <int kMax, typename F>
void WithGroupCount(int groups, F&& f) {
  if constexpr (kMax >= 3) {
    if (groups == 3) return f(std::integral_constant<int, 3>());
  }
  if constexpr (kMax >= 2) {
    if (groups == 2) return f(std::integral_constant<int, 2>());
  }
  return f(std::integral_constant<int, 1>());
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
    constexpr int kMaxGroups = MaxGroups(kP);
    // Lanes [i, i + count) add to consecutive elements of one sum array.
    auto interleaved = [&](std::size_t i, int count) {
      for (int m = 1; m < count; ++m) {
        if (lanes[i + m].sum != lanes[i].sum + m || lanes[i + m].sum_stride != lanes[i].sum_stride)
          return false;
      }
      return count > 0;
    };
    for (std::size_t i = 0; i < lanes.size();) {
      const int active =
          static_cast<int>(std::min<std::size_t>(kMaxGroups * kLanes, lanes.size() - i));
      if (interleaved(i, active / kLanes * kLanes)) {
        // Several groups per loop pay only with vector adds: the scalar adds of that many lanes
        // cost more than the overlap saves (measured).
        WithGroupCount<kMaxGroups>((active + kLanes - 1) / kLanes, [&](auto g) {
          AddLanes<kP, decltype(g)::value, true>(z, n, phi.data(), p, lanes.data() + i, active);
        });
        i += active;
        continue;
      }
      const int group = static_cast<int>(std::min<std::size_t>(kLanes, lanes.size() - i));
      if (group == kLanes && interleaved(i, kLanes)) {
        AddLanes<kP, 1, true>(z, n, phi.data(), p, lanes.data() + i, group);
      } else {
        AddLanes<kP, 1, false>(z, n, phi.data(), p, lanes.data() + i, group);
      }
      i += group;
    }
  });
}

void PartialPredictions(const Eigen::VectorXd& phi, const Eigen::VectorXd& state, double* partial) {
  const int p = static_cast<int>(phi.size());
  for (int m = 0; m < p; ++m) {
    double sm = 0.0;
    for (int i = m; i < p; ++i) sm = kernels::MulAdd(phi[i], state[i - m], sm);
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

bool ConstantGainLoopStable(const Eigen::VectorXd& phi, const Eigen::VectorXd& gain,
                            double* modulus) {
  const int p = static_cast<int>(phi.size());
  Eigen::VectorXd beta(p);
  Betas(phi.data(), gain.data(), p, beta.data(), 1);
  if (ar::IsStationaryAsStored(phi, beta)) return true;
  if (modulus != nullptr) *modulus = ar::MaxRootModulusAsStored(phi, beta);
  return false;
}

}  // namespace fogpipe::kalman
