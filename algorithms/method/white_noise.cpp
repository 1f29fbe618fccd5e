#include "algorithms/method/white_noise.h"

#include <algorithm>
#include <cmath>

namespace fogpipe::method {

double WhiteNoiseVariance(const Eigen::VectorXd& x) {
  const Eigen::Index n = x.size();
  if (n < 3) return 0.0;
  std::vector<double> diff(static_cast<std::size_t>(n - 1));
  for (Eigen::Index i = 0; i + 1 < n; ++i) diff[i] = x[i + 1] - x[i];
  auto median_of = [](std::vector<double>* v) {
    auto mid = v->begin() + static_cast<std::ptrdiff_t>(v->size() / 2);
    std::nth_element(v->begin(), mid, v->end());
    return *mid;
  };
  const double center = median_of(&diff);
  for (double& d : diff) d = std::abs(d - center);
  const double sigma_diff = 1.482602218505602 * median_of(&diff);
  if (sigma_diff > 0.0) return 0.5 * sigma_diff * sigma_diff;
  // Coarsely quantized data can repeat values so often that the MAD of the differences is 0;
  // fall back to the plain variance of the differences.
  double sum = 0.0;
  for (Eigen::Index i = 0; i + 1 < n; ++i) sum += (x[i + 1] - x[i]) * (x[i + 1] - x[i]);
  return 0.5 * sum / static_cast<double>(n - 1);
}

std::vector<double> ShareWhiteNoise(double white_noise_variance,
                                    const std::vector<double>& mean_period_samples,
                                    const std::vector<double>& imf_variance) {
  std::vector<double> weight(mean_period_samples.size(), 0.0);
  double total = 0.0;
  for (std::size_t k = 0; k < weight.size(); ++k) {
    const double t = mean_period_samples[k];
    if (std::isfinite(t) && t > 0.0) weight[k] = 1.0 / t;
    total += weight[k];
  }
  std::vector<double> r(weight.size(), 0.0);
  if (!(total > 0.0) || !(white_noise_variance > 0.0)) return r;
  for (std::size_t k = 0; k < r.size(); ++k) {
    r[k] = std::min(white_noise_variance * weight[k] / total, imf_variance[k]);
  }
  return r;
}

std::vector<double> ComponentVariances(const emd::EmdResult& decomposition) {
  const int num_imfs = static_cast<int>(decomposition.imfs.size());
  std::vector<double> variances(num_imfs + 1);
  for (int k = 0; k <= num_imfs; ++k) {
    const Eigen::VectorXd& c = k < num_imfs ? decomposition.imfs[k] : decomposition.residue;
    variances[k] = c.size() > 0 ? (c.array() - c.mean()).square().mean() : 0.0;
  }
  return variances;
}

std::vector<double> ComponentPeriods(const emd::EmdResult& decomposition,
                                     Eigen::Index num_samples) {
  const int num_imfs = static_cast<int>(decomposition.imfs.size());
  std::vector<double> periods(num_imfs + 1);
  for (int k = 0; k <= num_imfs; ++k) {
    periods[k] = k < num_imfs ? decomposition.imf_info[k].mean_period_samples
                              : static_cast<double>(num_samples);
  }
  return periods;
}

std::vector<double> ShareWhiteNoise(double white_noise_variance,
                                    const emd::EmdResult& decomposition, Eigen::Index num_samples) {
  return ShareWhiteNoise(white_noise_variance, ComponentPeriods(decomposition, num_samples),
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
