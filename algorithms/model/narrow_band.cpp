#include "algorithms/model/narrow_band.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>

#include "algorithms/common/units.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::model {
namespace {

// Adjacent bins of a Hann-windowed DFT of white noise are correlated: the windowed coefficient is
// X_k / 2 - (X_{k-1} + X_{k+1}) / 4, so the complex correlation is -2/3 at lag 1 and 1/6 at lag 2,
// and |X|^2 (Gaussian) has correlation 4/9 and 1/36. Welch's average keeps it. A sum over bins of
// a function that is smooth on the scale of a bin (the score of a band many bins wide) has its
// variance multiplied by 1 + 2 (4/9 + 1/36) = 35/18 against independent bins; the Whittle
// likelihood treats bins as independent, so its information (and -2 ln L drops) are divided by it.
constexpr double kHannBinCorrelation = 35.0 / 18.0;
constexpr double kMaxZeta = 0.9;  // the closed forms need zeta < 1 (underdamped)

// exp(x) - 1 - x without cancellation for small |x|.
std::complex<double> ExpMinusOneMinusX(std::complex<double> x) {
  if (std::abs(x) < 1e-3) return x * x * (0.5 + x * (1.0 / 6.0 + x / 24.0));
  return std::exp(x) - 1.0 - x;
}

// Structure function of the integrated band, D(t) (narrow_band.h).
double StructureFunction(const NarrowBand& band, double t) {
  const double w0 = 2 * units::kPi * band.f0_hz;
  const double zeta = std::min(band.zeta, kMaxZeta);
  const double wd = w0 * std::sqrt(1.0 - zeta * zeta);
  const std::complex<double> lambda(-zeta * w0, wd);
  const std::complex<double> c =
      band.sigma_rad_s * band.sigma_rad_s * std::complex<double>(1.0, -zeta * w0 / wd);
  return 2.0 * std::real(c * ExpMinusOneMinusX(lambda * t) / (lambda * lambda));
}

// Nelder-Mead (1965) simplex minimisation from x0 with initial steps `step`.
Eigen::VectorXd NelderMead(const std::function<double(const Eigen::VectorXd&)>& f,
                           const Eigen::VectorXd& x0, const Eigen::VectorXd& step, int iterations) {
  const long n = x0.size();
  std::vector<Eigen::VectorXd> simplex(n + 1, x0);
  std::vector<double> values(n + 1);
  for (long i = 0; i < n; ++i) simplex[i + 1][i] += step[i];
  for (long i = 0; i <= n; ++i) values[i] = f(simplex[i]);
  std::vector<long> order(n + 1);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    for (long i = 0; i <= n; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](long a, long b) { return values[a] < values[b]; });
    const long best = order[0], worst = order[n], second = order[n - 1];
    if (std::abs(values[worst] - values[best]) < 1e-10 * (1.0 + std::abs(values[best]))) break;
    Eigen::VectorXd centroid = Eigen::VectorXd::Zero(n);
    for (long i = 0; i < n; ++i) centroid += simplex[order[i]] / static_cast<double>(n);
    const Eigen::VectorXd reflected = centroid + (centroid - simplex[worst]);
    const double reflected_value = f(reflected);
    if (reflected_value < values[best]) {
      const Eigen::VectorXd expanded = centroid + 2.0 * (centroid - simplex[worst]);
      const double expanded_value = f(expanded);
      const bool expand = expanded_value < reflected_value;
      simplex[worst] = expand ? expanded : reflected;
      values[worst] = expand ? expanded_value : reflected_value;
    } else if (reflected_value < values[second]) {
      simplex[worst] = reflected;
      values[worst] = reflected_value;
    } else {
      const Eigen::VectorXd contracted = centroid + 0.5 * (simplex[worst] - centroid);
      const double contracted_value = f(contracted);
      if (contracted_value < values[worst]) {
        simplex[worst] = contracted;
        values[worst] = contracted_value;
      } else {
        for (long i = 1; i <= n; ++i) {
          simplex[order[i]] = simplex[best] + 0.5 * (simplex[order[i]] - simplex[best]);
          values[order[i]] = f(simplex[order[i]]);
        }
      }
    }
  }
  long best = 0;
  for (long i = 1; i <= n; ++i)
    if (values[i] < values[best]) best = i;
  return simplex[best];
}

NarrowBand BandOf(const Eigen::VectorXd& x) {
  NarrowBand band;
  band.f0_hz = std::exp(x[1]);
  band.zeta = std::exp(x[2]);
  band.sigma_rad_s = std::exp(0.5 * x[3]);
  return band;
}

}  // namespace

double NarrowBandOneSidedPsd(const NarrowBand& band, double frequency_hz) {
  const double w0 = 2 * units::kPi * band.f0_hz, w = 2 * units::kPi * frequency_hz;
  const double detuning = w0 * w0 - w * w, damping = 2 * band.zeta * w0 * w;
  return 8 * band.zeta * w0 * w0 * w0 * band.sigma_rad_s * band.sigma_rad_s /
         (detuning * detuning + damping * damping);
}

double NarrowBandAllanVariance(const NarrowBand& band, double tau_s) {
  if (!(band.f0_hz > 0 && band.zeta > 0 && tau_s > 0)) return 0.0;
  return std::max(0.0, (4 * StructureFunction(band, tau_s) - StructureFunction(band, 2 * tau_s)) /
                           (2 * tau_s * tau_s));
}

Eigen::VectorXd SimulateNarrowBand(const NarrowBand& band, long n, double fs, std::uint64_t seed,
                                   long block) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(std::max(0L, n));
  if (!(band.f0_hz > 0 && band.zeta > 0 && band.zeta < 1 && band.sigma_rad_s > 0 && fs > 0))
    return x;
  const double w0 = 2 * units::kPi * band.f0_hz, dt = 1.0 / fs;
  const double decay = band.zeta * w0, wd = w0 * std::sqrt(1 - band.zeta * band.zeta);
  // exp(A dt) of A = [[0, 1], [-w0^2, -2 zeta w0]] (underdamped), and the step's noise covariance
  // P - Phi P Phi^T with P the stationary covariance.
  const double e = std::exp(-decay * dt), c = std::cos(wd * dt), s = std::sin(wd * dt);
  Eigen::Matrix2d phi;
  phi << e * (c + decay / wd * s), e * s / wd, -e * w0 * w0 / wd * s, e * (c - decay / wd * s);
  const double var = band.sigma_rad_s * band.sigma_rad_s;
  Eigen::Matrix2d stationary;
  stationary << var, 0, 0, w0 * w0 * var;
  const Eigen::Matrix2d step = stationary - phi * stationary * phi.transpose();
  // The step covariance is positive definite for dt > 0; its Cholesky factor colours the draws
  // (LDLT guards against rounding at tiny dt, where it is nearly singular).
  const Eigen::LDLT<Eigen::Matrix2d> ldlt(step);
  const Eigen::Matrix2d factor = ldlt.transpositionsP().transpose() *
                                 Eigen::Matrix2d(ldlt.matrixL()) *
                                 ldlt.vectorD().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  simulation::RandomSource random(seed);
  const double x0 = band.sigma_rad_s * random.Normal();
  const double v0 = w0 * band.sigma_rad_s * random.Normal();
  Eigen::Vector2d state(x0, v0);
  block = std::max(1L, block);
  for (long i = 0; i < n; ++i) {
    double sum = 0;
    for (long j = 0; j < block; ++j) {
      sum += state[0];
      const double first = random.Normal();
      const double second = random.Normal();
      state = phi * state + factor * Eigen::Vector2d(first, second);
    }
    x[i] = sum / block;
  }
  return x;
}

NarrowBandFitResult FitNarrowBand(const Spectrum& welch, const std::vector<double>& background,
                                  const std::vector<double>& fixed, int first_bin,
                                  const NarrowBandStart& start) {
  NarrowBandFitResult result;
  const int bins = static_cast<int>(welch.psd.size());
  if (bins < 8 || background.size() != welch.psd.size() ||
      !(fixed.empty() || fixed.size() == welch.psd.size()) || !(start.center_hz > 0)) {
    result.message = "no spectrum or no band to start from";
    return result;
  }
  const double bin_hz = welch.frequency_hz[1] - welch.frequency_hz[0];
  // Window: the failing band and 3.5 times its extent on either side (at least 20 bins), so that
  // the band's skirts and the local background level are both in it.
  const double extent = std::max(start.to_hz - start.from_hz, 2 * bin_hz);
  const double half = std::max(3.5 * extent, 20 * bin_hz);
  std::vector<int> window;
  for (int k = std::max(first_bin, 1); k + 1 < bins; ++k)
    if (std::abs(welch.frequency_hz[k] - start.center_hz) <= half && background[k] > 0)
      window.push_back(k);
  if (window.size() < 8) {
    result.message = "fewer than 8 bins around the band";
    return result;
  }
  const double nu = welch.dof;
  const double f_low = welch.frequency_hz[window.front()],
               f_high = welch.frequency_hz[window.back()];
  const auto other = [&](int k) { return fixed.empty() ? 0.0 : fixed[k]; };
  // -2 ln L (Whittle) over the window, up to a constant.
  const auto minus_two_log_l = [&](const Eigen::VectorXd& x) {
    const NarrowBand band = BandOf(x);
    if (!(band.f0_hz > f_low && band.f0_hz < f_high && band.zeta < kMaxZeta &&
          HalfPowerBandwidthHz(band) > 0.5 * bin_hz))
      return std::numeric_limits<double>::infinity();
    const double level = std::exp(x[0]);
    double sum = 0;
    for (int k : window) {
      const double s =
          level * background[k] + other(k) + NarrowBandOneSidedPsd(band, welch.frequency_hz[k]);
      sum += welch.psd[k] / s + std::log(s);
    }
    return nu * sum;
  };
  // Background alone (the level fitted, no new band): the null of the likelihood-ratio.
  const auto null_minus_two_log_l = [&](double log_level) {
    double sum = 0;
    for (int k : window) {
      const double s = std::exp(log_level) * background[k] + other(k);
      sum += welch.psd[k] / s + std::log(s);
    }
    return nu * sum;
  };
  double best_log_level = 0, null_value = std::numeric_limits<double>::infinity();
  for (double log_level = -3.0; log_level <= 3.0; log_level += 0.05) {
    const double value = null_minus_two_log_l(log_level);
    if (value < null_value) {
      null_value = value;
      best_log_level = log_level;
    }
  }
  null_value = NelderMead([&](const Eigen::VectorXd& y) { return null_minus_two_log_l(y[0]); },
                          Eigen::VectorXd::Constant(1, best_log_level),
                          Eigen::VectorXd::Constant(1, 0.02), 200)
                   .unaryExpr([&](double y) { return null_minus_two_log_l(y); })[0];
  // Start: zeta from the failing extent (a band of peak ratio ~10 fails where its Lorentzian
  // exceeds ~1, about +-3 half-widths, so extent ~ 6 zeta f0), power from the excess power.
  const double zeta0 = std::clamp(extent / (6.0 * start.center_hz), bin_hz / start.center_hz, 0.5);
  double power0 = start.excess_power;
  if (!(power0 > 0)) {
    power0 = 0;
    for (int k : window) power0 += std::max(welch.psd[k] - background[k] - other(k), 0.0) * bin_hz;
  }
  if (!(power0 > 0)) {
    result.message = "no excess power around the band";
    return result;
  }
  Eigen::VectorXd x(4);
  x << 0.0, std::log(start.center_hz), std::log(zeta0), std::log(power0);
  Eigen::VectorXd step(4);
  step << 0.1, std::min(0.5 * zeta0, 0.05), 0.5, 0.5;
  // The simplex is restarted twice: Nelder-Mead can stall on the ridge of (zeta, power).
  for (int restart = 0; restart < 3; ++restart) x = NelderMead(minus_two_log_l, x, step, 2000);
  const double best = minus_two_log_l(x);
  if (!std::isfinite(best)) {
    result.message = "the likelihood has no finite maximum in the window";
    return result;
  }
  // Information: Hessian of -ln L = (-2 ln L) / 2 by central differences in x.
  Eigen::Matrix4d hessian;
  const double h = 1e-3;
  for (int i = 0; i < 4; ++i)
    for (int j = i; j < 4; ++j) {
      auto at = [&](double di, double dj) {
        Eigen::VectorXd y = x;
        y[i] += di;
        y[j] += dj;
        return 0.5 * minus_two_log_l(y);
      };
      hessian(i, j) = hessian(j, i) = (at(h, h) - at(h, -h) - at(-h, h) + at(-h, -h)) / (4 * h * h);
    }
  // The likelihood's curvature at a minimum is positive definite; where it is not (a flat or
  // saddle direction), the standard errors are undefined and the fit is not offered as one.
  const Eigen::LLT<Eigen::Matrix4d> curvature(hessian);
  const bool curved = curvature.info() == Eigen::Success;
  const Eigen::Matrix4d covariance =
      kHannBinCorrelation *
      (curved ? curvature.solve(Eigen::Matrix4d::Identity()).eval()
              : Eigen::Matrix4d::Constant(std::numeric_limits<double>::quiet_NaN()));
  NarrowBand band = BandOf(x);
  auto se = [&](int i) { return std::sqrt(covariance(i, i)); };
  band.f0_se_hz = band.f0_hz * se(1);
  band.zeta_se = band.zeta * se(2);
  // ln(2 zeta f0) = ln 2 + x1 + x2 (the log parameters): its variance is C11 + C22 + 2 C12.
  band.bandwidth_se_hz =
      HalfPowerBandwidthHz(band) *
      std::sqrt(std::max(covariance(1, 1) + covariance(2, 2) + 2 * covariance(1, 2), 0.0));
  band.sigma_se_rad_s = 0.5 * band.sigma_rad_s * se(3);
  band.minus_two_log_likelihood_drop = (null_value - best) / kHannBinCorrelation;
  band.effective_bins = (bins - first_bin) / kHannBinCorrelation;
  result.ok = curved && band.f0_se_hz > 0 && band.zeta_se > 0 && band.sigma_se_rad_s > 0 &&
              std::isfinite(band.f0_se_hz) && std::isfinite(band.zeta_se) &&
              std::isfinite(band.sigma_se_rad_s);
  result.band = band;
  result.message = result.ok ? "Whittle fit on " + std::to_string(window.size()) + " Welch bins"
                             : "singular information matrix";
  return result;
}

}  // namespace fogpipe::model
