#include "algorithms/model/angle_lattice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "algorithms/common/chi_square.h"
#include "algorithms/common/units.h"

namespace fogpipe::model {

bool AngleLatticeOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* message) {
    if (error) *error = message;
    return false;
  };
  if (max_sorted_samples < 16) return fail("angle_lattice.max_sorted_samples must be >= 16");
  if (!(level_tolerance > 0 && level_tolerance < 0.5))
    return fail("angle_lattice.level_tolerance must be in (0, 0.5)");
  if (!(min_fraction > 0 && min_fraction <= 1))
    return fail("angle_lattice.min_fraction must be in (0, 1]");
  if (!(max_levels >= 2)) return fail("angle_lattice.max_levels must be >= 2");
  if (whiteness_lags < 2) return fail("angle_lattice.whiteness_lags must be >= 2");
  if (!(coarse_level > 0 && coarse_level < 1))
    return fail("angle_lattice.coarse_level must be in (0, 1)");
  if (!(max_spread_steps > 0)) return fail("angle_lattice.max_spread_steps must be > 0");
  return true;
}

namespace {

struct Level {
  double value = 0;
  double count = 0;
};

// The distinct levels of the sorted values: neighbours closer than `merge` are one level (its
// value the mean).
std::vector<Level> DistinctLevels(std::vector<double> values, double merge) {
  std::sort(values.begin(), values.end());
  std::vector<Level> levels;
  double sum = 0, count = 0, last = 0;
  for (double value : values) {
    if (count > 0 && value - last > merge) {
      levels.push_back({sum / count, count});
      sum = 0;
      count = 0;
    }
    sum += value;
    count += 1;
    last = value;
  }
  if (count > 0) levels.push_back({sum / count, count});
  return levels;
}

// The step and offset refined by weighted least squares of the levels on their lattice indices
// n_j = round((v_j - v_ref) / q0): v_j = c + q n_j. Returns false when the levels are not on the
// lattice of q0 (a level further than `tolerance` q0 from it).
bool RefineStep(const std::vector<Level>& levels, double q0, double tolerance, double* step,
                double* step_se, double* offset) {
  const auto reference =
      std::max_element(levels.begin(), levels.end(),
                       [](const Level& lhs, const Level& rhs) { return lhs.count < rhs.count; });
  double sw = 0, sn = 0, sv = 0;
  std::vector<double> index(levels.size());
  for (size_t j = 0; j < levels.size(); ++j) {
    const double x = (levels[j].value - reference->value) / q0;
    index[j] = std::round(x);
    if (std::abs(x - index[j]) > tolerance) return false;
    sw += levels[j].count;
    sn += levels[j].count * index[j];
    sv += levels[j].count * levels[j].value;
  }
  const double mean_n = sn / sw, mean_v = sv / sw;
  double snn = 0, snv = 0;
  for (size_t j = 0; j < levels.size(); ++j) {
    snn += levels[j].count * (index[j] - mean_n) * (index[j] - mean_n);
    snv += levels[j].count * (index[j] - mean_n) * (levels[j].value - mean_v);
  }
  if (!(snn > 0)) return false;
  *step = snv / snn;
  double rss = 0;
  for (size_t j = 0; j < levels.size(); ++j) {
    const double r = levels[j].value - mean_v - *step * (index[j] - mean_n);
    rss += levels[j].count * r * r;
  }
  // The levels' weighted residual variance over the subsample's degrees of freedom; at least
  // float32's relative resolution 2^-24 of the step: a recording may be stored as float32, whose
  // rounding of levels symmetric about zero is collinear and invisible to the residuals.
  *step_se =
      std::max(std::sqrt(rss / std::max(1.0, sw - 2) / snn), std::ldexp(std::abs(*step), -24));
  // c reduced to [-q/2, q/2): the lattice c + q Z is the same for every c' = c + q m.
  const double c = mean_v - *step * mean_n;
  *offset = c - *step * std::round(c / *step);
  return true;
}

std::string Describe(const AngleLattice& lattice) {
  if (!lattice.evaluated) return "angle lattice not evaluated";
  if (!lattice.on_lattice) return "no angle lattice";
  const char* reading =
      lattice.coarse ? "coarse: the error is not white"
      : lattice.whiteness_statistic > lattice.whiteness_critical
          ? "not coarse: the increments are correlated but spread over many steps (noise "
            "or signal, not the quantizer's pattern)"
          : "error white";
  char text[384];
  std::snprintf(text, sizeof(text),
                "angle counter, step %.4g arcsec, %s (increments' correlation at lags 2-%d: %.4g "
                "against %.4g; spread %.3g steps)",
                lattice.step_rad * units::kArcsecPerRad, reading, lattice.whiteness_dof + 1,
                lattice.whiteness_statistic, lattice.whiteness_critical, lattice.spread_steps);
  return text;
}

}  // namespace

AngleLattice DetectAngleLattice(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                                const AngleLatticeOptions& options) {
  AngleLattice lattice;
  std::vector<double> increments;
  increments.reserve(static_cast<size_t>(rate_rad_s.size()));
  for (Eigen::Index k = 0; k < rate_rad_s.size(); ++k)
    if (std::isfinite(rate_rad_s[k])) increments.push_back(rate_rad_s[k] / sample_rate_hz);
  const size_t n = increments.size();
  if (!options.IsValid(nullptr) || !(sample_rate_hz > 0) ||
      n < static_cast<size_t>(4 * options.whiteness_lags)) {
    lattice.message = Describe(lattice);
    return lattice;
  }
  lattice.evaluated = true;
  const size_t stride = std::max<size_t>(1, n / static_cast<size_t>(options.max_sorted_samples));
  std::vector<double> subsample;
  double largest = 0;
  for (size_t k = 0; k < n; k += stride) {
    subsample.push_back(increments[k]);
    largest = std::max(largest, std::abs(increments[k]));
  }
  const std::vector<Level> levels = DistinctLevels(subsample, 1e-6 * largest);
  lattice.levels = static_cast<int>(levels.size());
  // Continuous data: most values are distinct.
  if (levels.size() < 2 || 2 * levels.size() > subsample.size()) {
    lattice.message = Describe(lattice);
    return lattice;
  }
  std::vector<double> gaps(levels.size() - 1);
  for (size_t j = 0; j + 1 < levels.size(); ++j) gaps[j] = levels[j + 1].value - levels[j].value;
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  const double q0 = gaps[gaps.size() / 2];
  double step = 0, step_se = 0, offset = 0;
  if (!(q0 > 0) || !RefineStep(levels, q0, options.level_tolerance, &step, &step_se, &offset) ||
      !(step > 0)) {
    lattice.message = Describe(lattice);
    return lattice;
  }
  double low = increments[0], high = increments[0], on = 0, mean = 0;
  for (double a : increments) {
    const double x = (a - offset) / step;
    on += std::abs(x - std::round(x)) <= options.level_tolerance;
    low = std::min(low, a);
    high = std::max(high, a);
    mean += a;
  }
  mean /= static_cast<double>(n);
  lattice.on_lattice_fraction = on / static_cast<double>(n);
  lattice.on_lattice = lattice.on_lattice_fraction >= options.min_fraction &&
                       (high - low) / step <= options.max_levels;
  if (!lattice.on_lattice) {
    lattice.message = Describe(lattice);
    return lattice;
  }
  lattice.step_rad = step;
  lattice.step_se_rad = step_se;
  lattice.offset_rad = offset;
  // The portmanteau of the increments over lags 2..L (header comment).
  const int lags = options.whiteness_lags;
  std::vector<double> r(static_cast<size_t>(lags) + 1, 0.0);
  double variance = 0;
  for (size_t k = 0; k < n; ++k) {
    const double d = increments[k] - mean;
    variance += d * d;
    for (int h = 1; h <= lags && static_cast<size_t>(h) <= k; ++h)
      r[static_cast<size_t>(h)] += d * (increments[k - static_cast<size_t>(h)] - mean);
  }
  lattice.spread_steps = std::sqrt(variance / static_cast<double>(n)) / step;
  if (variance > 0) {
    for (int h = 1; h <= lags; ++h) r[static_cast<size_t>(h)] /= variance;
    double sum = 0;
    for (int h = 2; h <= lags; ++h) sum += r[static_cast<size_t>(h)] * r[static_cast<size_t>(h)];
    lattice.lag1_correlation = r[1];
    lattice.whiteness_statistic = static_cast<double>(n) * sum / (1.0 + 2.0 * r[1] * r[1]);
  } else {
    lattice.lag1_correlation = 0;
    lattice.whiteness_statistic = 0;
  }
  lattice.whiteness_dof = lags - 1;
  lattice.whiteness_critical = stats::ChiSquareQuantile(1.0 - options.coarse_level, lags - 1);
  lattice.coarse = lattice.whiteness_statistic > lattice.whiteness_critical &&
                   lattice.spread_steps <= options.max_spread_steps;
  lattice.message = Describe(lattice);
  return lattice;
}

}  // namespace fogpipe::model
