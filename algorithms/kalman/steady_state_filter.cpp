#include "algorithms/kalman/steady_state_filter.h"

#include <vector>

namespace fogpipe::kalman {
namespace {

// Pairwise sum of a fixed-size array: a tree of depth log2(N) instead of a chain of N additions.
template <int N>
inline double TreeSum(const double* v) {
  if constexpr (N <= 0) {
    return 0.0;
  } else if constexpr (N == 1) {
    return v[0];
  } else {
    constexpr int kHalf = N / 2;
    return TreeSum<kHalf>(v) + TreeSum<N - kHalf>(v + kHalf);
  }
}

template <int P>
inline double LaggedSum(const double* phi, const double* x) {
  // c = sum_{i>=1} phi_i x_{i-1}
  double t[P > 1 ? P - 1 : 1];
  for (int i = 1; i < P; ++i) t[i - 1] = phi[i] * x[i - 1];
  return TreeSum<P - 1>(t);
}

template <int P, bool kStoreInnovations>
void FixedKernel(const double* z, long long n, double mean, const double* phi_in,
                 const double* gain_in, double* state, double* filtered, double* innovations) {
  double phi[P], g[P], x[P], t[P];
  for (int i = 0; i < P; ++i) {
    phi[i] = phi_in[i];
    g[i] = gain_in[i];
    x[i] = state[i];
  }
  for (int i = 0; i < P; ++i) t[i] = phi[i] * g[i];
  const double kappa = TreeSum<P>(t);
  for (int i = 0; i < P; ++i) t[i] = phi[i] * x[i];
  double pred = TreeSum<P>(t);
  double c = LaggedSum<P>(phi, x);
  for (long long k = 0; k < n; ++k) {
    const double e = (z[k] - mean) - pred;
    const double next_pred = (phi[0] * pred + c) + kappa * e;
    double xn[P];
    xn[0] = pred + g[0] * e;
    for (int i = 1; i < P; ++i) xn[i] = x[i - 1] + g[i] * e;
    filtered[k] = xn[0] + mean;
    if constexpr (kStoreInnovations) innovations[k] = e;
    c = LaggedSum<P>(phi, xn);
    for (int i = 0; i < P; ++i) x[i] = xn[i];
    pred = next_pred;
  }
  for (int i = 0; i < P; ++i) state[i] = x[i];
}

// Any order: the plain form with runtime loops.
void GenericKernel(const double* z, long long n, double mean, const double* phi, const double* g,
                   int p, double* state, double* filtered, double* innovations) {
  std::vector<double> x(state, state + p);
  for (long long k = 0; k < n; ++k) {
    double pred = 0.0;
    for (int i = 0; i < p; ++i) pred += phi[i] * x[i];
    const double e = (z[k] - mean) - pred;
    for (int i = p - 1; i >= 1; --i) x[i] = x[i - 1] + g[i] * e;
    x[0] = pred + g[0] * e;
    filtered[k] = x[0] + mean;
    if (innovations) innovations[k] = e;
  }
  for (int i = 0; i < p; ++i) state[i] = x[i];
}

template <int P>
void Dispatch(const double* z, long long n, double mean, const double* phi, const double* g,
              double* state, double* filtered, double* innovations) {
  if (innovations) {
    FixedKernel<P, true>(z, n, mean, phi, g, state, filtered, innovations);
  } else {
    FixedKernel<P, false>(z, n, mean, phi, g, state, filtered, nullptr);
  }
}

}  // namespace

void SteadyStateFilter(const double* z, long long n, double mean, const Eigen::VectorXd& phi,
                       const Eigen::VectorXd& gain, Eigen::VectorXd* state, double* filtered,
                       double* innovations) {
  const int p = static_cast<int>(phi.size());
  double* s = state->data();
  switch (p) {
    case 1:
      return Dispatch<1>(z, n, mean, phi.data(), gain.data(), s, filtered, innovations);
    case 2:
      return Dispatch<2>(z, n, mean, phi.data(), gain.data(), s, filtered, innovations);
    case 3:
      return Dispatch<3>(z, n, mean, phi.data(), gain.data(), s, filtered, innovations);
    case 4:
      return Dispatch<4>(z, n, mean, phi.data(), gain.data(), s, filtered, innovations);
    case 5:
      return Dispatch<5>(z, n, mean, phi.data(), gain.data(), s, filtered, innovations);
    case 6:
      return Dispatch<6>(z, n, mean, phi.data(), gain.data(), s, filtered, innovations);
    case 7:
      return Dispatch<7>(z, n, mean, phi.data(), gain.data(), s, filtered, innovations);
    case 8:
      return Dispatch<8>(z, n, mean, phi.data(), gain.data(), s, filtered, innovations);
    default:
      return GenericKernel(z, n, mean, phi.data(), gain.data(), p, s, filtered, innovations);
  }
}

}  // namespace fogpipe::kalman
