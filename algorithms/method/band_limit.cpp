#include "algorithms/method/band_limit.h"

#include <algorithm>
#include <vector>

#include "algorithms/filters/butterworth.h"

namespace fogpipe::method {

bool BandLimitOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (!(cutoff_ratio >= 0.0 && cutoff_ratio <= 1.0))
    return fail("band_limit.cutoff_ratio must be in [0, 1]");
  if (order != 2 && order != 4) return fail("band_limit.order must be 2 or 4");
  if (!(min_cycles >= 1.0)) return fail("band_limit.min_cycles must be >= 1");
  return true;
}

void BandLimiter::Next(Eigen::VectorXd* imf, emd::ImfInfo* info) {
  if (!(options_.cutoff_ratio > 0.0)) return;
  if (pending_) {
    *imf += leak_;
    pending_ = false;
  }
  // The band of the component as it stands, the previous one's leakage included.
  emd::DescribeImf(*imf, info);
  const Eigen::Index n = imf->size();
  const double period = info->mean_period_samples;
  if (!(period > 0.0) || static_cast<double>(n) / period < options_.min_cycles) return;
  const double cutoff = options_.cutoff_ratio / period;  // cycles per sample
  if (!(cutoff < 0.45)) return;  // below the Nyquist band edge with room for the design
  // The odd-reflection pad of the low-pass, at most the record: the slowest IMFs' cutoffs have
  // periods near the record length, and a longer pad only repeats the record.
  const Eigen::Index pad = std::min<Eigen::Index>(filters::ButterworthPad(cutoff, 1.0), n - 1);
  filters::FilterForwardBackward(filters::ButterworthSections(options_.order, cutoff, 1.0), *imf,
                                 pad, &work_, &leak_);
  *imf -= leak_;
  emd::DescribeImf(*imf, info);
  pending_ = true;
}

void BandLimiter::Finish(Eigen::VectorXd* residue) {
  if (pending_) *residue += leak_;
  pending_ = false;
  // Up to 2 N doubles that the filters after the decomposition can use.
  leak_ = Eigen::VectorXd();
  work_ = std::vector<double>();
}

void BandLimitImfs(const BandLimitOptions& options, emd::EmdResult* d) {
  BandLimiter limiter(options);
  for (std::size_t k = 0; k < d->imfs.size(); ++k) limiter.Next(&d->imfs[k], &d->imf_info[k]);
  limiter.Finish(&d->residue);
}

}  // namespace fogpipe::method
