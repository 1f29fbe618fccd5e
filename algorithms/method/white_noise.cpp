#include "algorithms/method/white_noise.h"

#include <algorithm>
#include <cmath>

namespace fogpipe::method {

namespace {

// Variance of d_t = x_t - x_{t-lag} by a robust scale: (1.4826 MAD)^2, or the plain mean square
// when more than half of the differences are equal (coarse quantization: MAD 0).
double DifferenceVariance(const Eigen::VectorXd& x, Eigen::Index lag) {
  const Eigen::Index n = x.size();
  std::vector<double> diff(static_cast<std::size_t>(n - lag));
  for (Eigen::Index i = 0; i + lag < n; ++i) diff[i] = x[i + lag] - x[i];
  auto median_of = [](std::vector<double>* v) {
    auto mid = v->begin() + static_cast<std::ptrdiff_t>(v->size() / 2);
    std::nth_element(v->begin(), mid, v->end());
    return *mid;
  };
  const double center = median_of(&diff);
  for (double& d : diff) d = std::abs(d - center);
  const double sigma = 1.482602218505602 * median_of(&diff);
  if (sigma > 0.0) return sigma * sigma;
  double sum = 0.0;
  for (Eigen::Index i = 0; i + lag < n; ++i) sum += (x[i + lag] - x[i]) * (x[i + lag] - x[i]);
  return sum / static_cast<double>(n - lag);
}

}  // namespace

WhiteNoiseLevels EstimateWhiteNoiseLevels(const Eigen::VectorXd& x, const ForEach& for_each) {
  WhiteNoiseLevels out;
  if (x.size() < 4) return out;
  double v[2] = {0.0, 0.0};  // lag 1: 2 u + 6 v; lag 2: 2 u + 4 v
  const auto one = [&](int i) { v[i] = DifferenceVariance(x, i + 1); };
  if (for_each) {
    for_each(2, one);
  } else {
    one(0);
    one(1);
  }
  const double v1 = v[0], v2 = v[1];
  double angle = 0.5 * (v1 - v2);
  double rate = 0.5 * (3.0 * v2 - 2.0 * v1);
  // Sampling noise can make one of them negative; the total u + 2 v = v2 / 2 is kept.
  if (angle < 0.0) angle = 0.0, rate = 0.5 * v2;
  if (rate < 0.0) rate = 0.0, angle = 0.25 * v2;
  out.rate_variance = rate;
  out.angle_variance = angle;
  return out;
}

std::vector<double> ShareWhiteNoise(const WhiteNoiseLevels& levels,
                                    const std::vector<double>& mean_period_samples,
                                    const std::vector<double>& imf_variance) {
  // Weights 1/T (white) and 1/T^3 (white angle noise: a rate spectrum rising like f^2), each
  // normalised over the components.
  std::vector<double> white(mean_period_samples.size(), 0.0), blue(white.size(), 0.0);
  double white_total = 0.0, blue_total = 0.0;
  for (std::size_t k = 0; k < white.size(); ++k) {
    const double t = mean_period_samples[k];
    if (!(std::isfinite(t) && t > 0.0)) continue;
    white[k] = 1.0 / t;
    blue[k] = 1.0 / (t * t * t);
    white_total += white[k];
    blue_total += blue[k];
  }
  std::vector<double> r(white.size(), 0.0);
  for (std::size_t k = 0; k < r.size(); ++k) {
    double share = 0.0;
    if (white_total > 0.0 && levels.rate_variance > 0.0)
      share += levels.rate_variance * white[k] / white_total;
    if (blue_total > 0.0 && levels.angle_variance > 0.0)
      share += 2.0 * levels.angle_variance * blue[k] / blue_total;
    r[k] = std::min(share, imf_variance[k]);
  }
  return r;
}

double ComponentVariance(const Eigen::VectorXd& c) {
  return c.size() > 0 ? (c.array() - c.mean()).square().mean() : 0.0;
}

std::vector<double> ComponentVariances(const emd::EmdResult& decomposition) {
  const int num_imfs = static_cast<int>(decomposition.imfs.size());
  std::vector<double> variances(num_imfs + 1);
  for (int k = 0; k <= num_imfs; ++k) {
    variances[k] = ComponentVariance(k < num_imfs ? decomposition.imfs[k] : decomposition.residue);
  }
  return variances;
}

std::vector<double> ComponentPeriods(const emd::EmdResult& decomposition,
                                     Eigen::Index num_samples) {
  const int num_imfs = static_cast<int>(decomposition.imf_info.size());
  std::vector<double> periods(num_imfs + 1);
  for (int k = 0; k <= num_imfs; ++k) {
    periods[k] = k < num_imfs ? decomposition.imf_info[k].mean_period_samples
                              : static_cast<double>(num_samples);
  }
  return periods;
}

std::vector<double> ShareWhiteNoise(const WhiteNoiseLevels& levels,
                                    const emd::EmdResult& decomposition, Eigen::Index num_samples) {
  return ShareWhiteNoise(levels, ComponentPeriods(decomposition, num_samples),
                         ComponentVariances(decomposition));
}

const char* ToString(ComponentNoiseRule rule) {
  switch (rule) {
    case ComponentNoiseRule::kShareOfInnovation:
      return "share";
    case ComponentNoiseRule::kInnovationMatch:
      return "innovation";
  }
  return "unknown";
}

bool ParseComponentNoiseRule(const std::string& text, ComponentNoiseRule* rule) {
  for (ComponentNoiseRule r :
       {ComponentNoiseRule::kShareOfInnovation, ComponentNoiseRule::kInnovationMatch}) {
    if (text == ToString(r)) {
      *rule = r;
      return true;
    }
  }
  return false;
}

FilterNoise ComponentFilterNoise(ComponentNoiseRule rule, double white_share, double variance,
                                 double innovation_variance) {
  FilterNoise out;
  if (rule == ComponentNoiseRule::kInnovationMatch) {
    out.r = white_share;
    return out;
  }
  // The white fraction of the component (ShareWhiteNoise caps the share at the variance).
  const double fraction = variance > 0.0 ? std::min(white_share / variance, 1.0) : 1.0;
  out.r = fraction * innovation_variance;
  if (fraction >= 1.0) {
    out.q = 0.0;
    out.pure_noise = true;
  }
  return out;
}

}  // namespace fogpipe::method
