#include "algorithms/allan/noise_id.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/common/units.h"

namespace fogpipe::allan {
namespace {

constexpr long long kMinAcfPoints = 30;  // Riley & Greenhall 2004: the lag-1 method needs ~30.
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Lag-1 autocorrelation r1 = sum (w_k - mu)(w_{k+1} - mu) / sum (w_k - mu)^2 (Riley 2004 eq. 2).
double Lag1Autocorrelation(const std::vector<double>& w) {
  const size_t n = w.size();
  double mu = 0.0;
  for (double v : w) mu += v;
  mu /= static_cast<double>(n);
  double num = 0.0, den = 0.0;
  for (size_t k = 0; k + 1 < n; ++k) num += (w[k] - mu) * (w[k + 1] - mu);
  for (double v : w) den += (v - mu) * (v - mu);
  return den > 0.0 ? num / den : 0.0;
}

NoiseId Lag1Method(std::vector<double> w, int dmax) {
  NoiseId id;
  id.method = NoiseIdMethod::kLag1Autocorrelation;
  for (int d = 0;; ++d) {
    const double r1 = Lag1Autocorrelation(w);
    const double rho = r1 / (1.0 + r1);
    if (rho < 0.25 || d >= dmax) {
      id.alpha_estimate = -2.0 * (rho + d);
      id.alpha = static_cast<int>(-std::lround(2.0 * rho)) - 2 * d;
      return id;
    }
    for (size_t k = 0; k + 1 < w.size(); ++k) w[k] = w[k + 1] - w[k];
    w.pop_back();
  }
}

// Expected B1 = (N-sample variance) / (two-sample variance) of N averages for phase-noise exponent
// mu = -alpha - 1 (Howe et al. 2000, Table 3; mu = -2 covers white and flicker PM).
double ExpectedB1(double n, int mu) {
  switch (mu) {
    case 2:
      return n * (n + 1.0) / 6.0;
    case 1:
      return n / 2.0;
    case 0:
      return n * std::log(n) / (2.0 * (n - 1.0) * std::log(2.0));
    case -1:
      return 1.0;
    case -2:
      return (n * n - 1.0) / (1.5 * n * (n - 1.0));
  }
  return kNaN;
}

// Overlapping Allan variance at factor m from the phase (tau0 units), and R(n) = Mod AVAR / AVAR.
struct AllanAndModified {
  double avar = kNaN;
  double mvar = kNaN;
};

AllanAndModified OverlappingAllanAndModified(const Eigen::VectorXd& x, long long m) {
  AllanAndModified out;
  const long long n_phase = x.size();
  const long long count = n_phase - 2 * m;  // second differences D_i, i < count
  const long long windows = n_phase - 3 * m + 1;
  if (count < 1) return out;
  auto diff2 = [&](long long i) { return x[i + 2 * m] - 2.0 * x[i + m] + x[i]; };
  double avar_sum = 0.0;
  for (long long i = 0; i < count; ++i) avar_sum += diff2(i) * diff2(i);
  const double md = static_cast<double>(m);
  out.avar = avar_sum / (2.0 * md * md * static_cast<double>(count));
  if (windows < 1) return out;
  double window = 0.0;  // sum of m consecutive D_i, slid along
  for (long long i = 0; i < m; ++i) window += diff2(i);
  double mvar_sum = 0.0;
  for (long long j = 0; j < windows; ++j) {
    mvar_sum += window * window;
    if (j + 1 < windows) window += diff2(j + m) - diff2(j);
  }
  out.mvar = mvar_sum / (2.0 * md * md * md * md * static_cast<double>(windows));
  return out;
}

NoiseId B1Method(const Eigen::VectorXd& phase, const std::vector<double>& z, long long m, int d) {
  NoiseId id;
  id.method = NoiseIdMethod::kB1Ratio;
  id.alpha_estimate = kNaN;
  const double n = static_cast<double>(z.size());
  double mu_z = 0.0;
  for (double v : z) mu_z += v;
  mu_z /= n;
  double var = 0.0;
  for (double v : z) var += (v - mu_z) * (v - mu_z);
  var /= (n - 1.0) * static_cast<double>(m) * static_cast<double>(m);  // z is m x the average
  // The Allan variance in the ratio is the overlapping estimate at m, the better estimate of the
  // same quantity; with it, our types agree with Stable32's in more of the few-average rows of the
  // reference reports than with the two-sample variance of the same N averages.
  const AllanAndModified allan = OverlappingAllanAndModified(phase, m);
  const double b1 = allan.avar > 0.0 ? var / allan.avar : 1.0;
  // Highest mu whose boundary (geometric mean of neighbouring expectations) b1 exceeds; the
  // Allan variance does not converge for mu = 2 (alpha = -3), so that class is Hadamard only.
  const int mu_max = d >= 3 ? 2 : 1;
  int mu = -2;
  for (int cand = mu_max; cand > -2; --cand) {
    if (b1 > std::sqrt(ExpectedB1(n, cand) * ExpectedB1(n, cand - 1))) {
      mu = cand;
      break;
    }
  }
  if (mu > -2) {
    id.alpha = -mu - 1;
    return id;
  }
  // Phase noise: white PM has R(n) = 1/m, flicker PM ~ 3.37 / (1.04 + 3 ln(pi m)) (TN 1337).
  id.method = NoiseIdMethod::kB1AndRn;
  const double md = static_cast<double>(m);
  const double rn = allan.mvar / allan.avar;
  const double boundary = std::sqrt((1.0 / md) * 3.37 / (1.04 + 3.0 * std::log(units::kPi * md)));
  id.alpha = (rn > boundary || !(rn == rn)) ? 1 : 2;
  return id;
}

}  // namespace

NoiseId IdentifyNoise(const Eigen::VectorXd& phase, long long m, int d) {
  NoiseId id;
  const long long n = phase.size() - 1;
  const long long averages = m >= 1 ? n / m : 0;
  if (averages < 4) {
    id.alpha_estimate = kNaN;
    return id;
  }
  // m-averaged frequency (times m; the scale does not matter for either method).
  std::vector<double> z(static_cast<size_t>(averages));
  for (long long k = 0; k < averages; ++k) z[k] = phase[(k + 1) * m] - phase[k * m];
  id = averages >= kMinAcfPoints ? Lag1Method(std::move(z), d) : B1Method(phase, z, m, d);
  id.alpha = std::clamp(id.alpha, 2 - 2 * d, 2);
  return id;
}

}  // namespace fogpipe::allan
